//! What every example shares: the repository's models wherever the example is run
//! from, one named output folder, and errors shown as their message.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// A file of the repository's `models/` folder, found from the crate's own folder,
/// so the example runs from any working directory.
#[allow(dead_code, reason = "not every example reads a model")]
pub fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("models").join(name)
}

/// The folder an example writes into: `example-output/NAME/` under the working
/// directory, created; printed by [`run`].
pub fn output_folder(name: &str) -> std::io::Result<PathBuf> {
    let folder = std::env::current_dir()?.join("example-output").join(name);
    std::fs::create_dir_all(&folder)?;
    Ok(folder)
}

/// Runs an example's body: on success prints where its files are, on failure the
/// error's message (not its debug form) and exits with status 1.
pub fn run(name: &str, body: impl FnOnce(&Path) -> octsolid::Result<()>) -> ExitCode {
    let result = output_folder(name)
        .map_err(|source| octsolid::Error::Io { path: PathBuf::from("example-output").join(name), source })
        .and_then(|folder| body(&folder).map(|()| folder));
    match result {
        Ok(folder) => {
            println!("wrote into {}", folder.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{name}: error: {e}");
            ExitCode::FAILURE
        }
    }
}

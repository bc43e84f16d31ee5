//! Writes the report: the plots under `docs/images/` next to the Markdown file, then
//! the Markdown file with only its report section replaced (atomically).

use std::path::{Path, PathBuf};

use super::markdown::{render_section, splice_section};
use super::matrix::MatrixResults;
use super::plots::{build_plot, mrays_plot};
use octsolid::io::write_atomic;
use octsolid::{Error, Result};

/// Folder of the plots, relative to the Markdown file.
pub const IMAGES: &str = "docs/images";

/// Writes the plots and splices the section into `markdown` (created when missing);
/// returns the files written.
pub fn write_report(results: &MatrixResults, markdown: &Path) -> Result<Vec<PathBuf>> {
    let base = markdown.parent().unwrap_or(Path::new(""));
    let images = base.join(IMAGES);
    std::fs::create_dir_all(&images).map_err(|source| Error::Io { path: images.clone(), source })?;
    let mut names = Vec::new();
    let mut written = Vec::new();
    for &scene in &results.options.scenes {
        let name = format!("bvh-mrays-{}.png", scene.name());
        mrays_plot(results, scene, &images.join(&name))?;
        written.push(images.join(&name));
        names.push(name);
    }
    let name = "bvh-build.png".to_string();
    build_plot(results, &images.join(&name))?;
    written.push(images.join(&name));
    names.push(name);

    let existing = match std::fs::read_to_string(markdown) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(source) => return Err(Error::Io { path: markdown.to_path_buf(), source }),
    };
    let text = splice_section(&existing, &render_section(results, IMAGES, &names), markdown)?;
    write_atomic(markdown, |w| w.write_all(text.as_bytes()))?;
    written.push(markdown.to_path_buf());
    Ok(written)
}

//! Writes the report: the plots under `docs/images/` (the `images/` folder of a Markdown
//! file in `docs/`), then the Markdown file with only its report section replaced
//! (atomically), or the whole page when the file is new.

use std::path::{Path, PathBuf};

use super::markdown::{page, render_section, splice_section};
use super::matrix::MatrixResults;
use super::plots::{build_plot, mrays_plot};
use octsolid::io::write_atomic;
use octsolid::{Error, Result};

/// Folder of the plots, relative to a Markdown file at the repository's top.
pub const IMAGES: &str = "docs/images";

/// Folder of the plots relative to `markdown`: `images` for a file in a `docs` folder
/// (the default, `docs/bvh-report.md`), [`IMAGES`] otherwise; so the plots land in
/// `docs/images/` either way.
#[must_use]
pub fn images_for(markdown: &Path) -> &'static str {
    let in_docs = markdown.parent().and_then(Path::file_name).is_some_and(|name| name == "docs");
    if in_docs { "images" } else { IMAGES }
}

/// Writes the plots and splices the section into `markdown`; a missing or empty file
/// becomes the whole page ([`page`]). Returns the files written.
pub fn write_report(results: &MatrixResults, markdown: &Path) -> Result<Vec<PathBuf>> {
    let base = markdown.parent().unwrap_or(Path::new(""));
    let relative = images_for(markdown);
    let images = base.join(relative);
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
    let section = render_section(results, relative, &names);
    let text = if existing.trim().is_empty() {
        page(&section, if relative == IMAGES { "" } else { "../" })
    } else {
        splice_section(&existing, &section, markdown)?
    };
    write_atomic(markdown, |w| w.write_all(text.as_bytes()))?;
    written.push(markdown.to_path_buf());
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plots_land_in_docs_images_from_docs_or_from_the_top() {
        assert_eq!(images_for(Path::new("docs/bvh-report.md")), "images");
        assert_eq!(images_for(Path::new("BENCHMARKS.md")), IMAGES);
        assert_eq!(images_for(Path::new("out/report.md")), IMAGES);
    }
}

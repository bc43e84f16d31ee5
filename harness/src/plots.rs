//! The report's plots as PNG: Mrays/s against depth for each contender (one image a
//! scene, a panel a ray kind, all threads), and build time against the solid's octree
//! node count. Text is drawn with the DejaVu Sans font embedded in the library
//! (`assets/fonts`, Bitstream Vera licence), so no system font or library is needed.

use std::path::Path;
use std::sync::Once;

use image::RgbImage;
use plotters::prelude::*;

use super::matrix::{ContenderKind, MatrixResults};
use super::rays::RayKind;
use super::scenes::SceneKind;
use octsolid::{Error, Result};

/// The embedded font.
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Registers the embedded font as `sans-serif` once.
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is a constant of the build; it parses.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// A colour a contender, the same in every plot.
fn color(kind: ContenderKind) -> RGBColor {
    match kind {
        ContenderKind::Octree => RGBColor(200, 60, 20),
        ContenderKind::Tree64 => RGBColor(240, 150, 30),
        ContenderKind::ObvhsFaces => RGBColor(30, 90, 200),
        ContenderKind::BvhFaces => RGBColor(20, 150, 90),
        ContenderKind::ObvhsMesh => RGBColor(120, 60, 180),
        ContenderKind::BvhMesh => RGBColor(150, 130, 20),
        ContenderKind::EmbreeFaces => RGBColor(0, 160, 200),
        ContenderKind::EmbreePacketsFaces => RGBColor(110, 200, 230),
        ContenderKind::EmbreeMesh => RGBColor(200, 40, 140),
        ContenderKind::EmbreePacketsMesh => RGBColor(235, 130, 190),
    }
}

/// Plotting errors become [`Error::Io`] on the image's path.
fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) }
}

/// Draws into an RGB buffer of `w x h` with `draw`, then saves it atomically as PNG.
fn render_png(
    path: &Path,
    (w, h): (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend, plotters::coord::Shift>) -> std::result::Result<(), String>,
) -> Result<()> {
    register_font();
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(path, e))?;
        draw(&root).map_err(|e| plot_error(path, e))?;
        root.present().map_err(|e| plot_error(path, e))?;
    }
    let img = RgbImage::from_raw(w, h, buffer).ok_or_else(|| plot_error(path, "image buffer size"))?;
    octsolid::io::png::write(&img, path).map(|_| ())
}

/// Mrays/s against depth on all threads for `scene`: one panel a ray kind.
pub fn mrays_plot(r: &MatrixResults, scene: SceneKind, path: &Path) -> Result<()> {
    let threads = r.options.threads;
    let cases: Vec<_> = r.cases.iter().filter(|c| c.scene == scene).collect();
    let (d0, d1) = r.options.depths.iter().fold((u8::MAX, 0), |(a, b), &d| (a.min(d), b.max(d)));
    render_png(path, (1500, 480), |root| {
        let panels = root.split_evenly((1, RayKind::ALL.len()));
        for (panel, kind) in panels.iter().zip(RayKind::ALL) {
            let top = cases
                .iter()
                .flat_map(|c| c.contenders.iter().filter_map(move |x| x.speed(kind, threads)))
                .map(|s| s.mrays())
                .fold(0.1, f64::max);
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} - {} rays, {threads} threads", scene.name(), kind.name()), ("sans-serif", 20))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(i32::from(d0) - 1..i32::from(d1) + 1, 0.0..top * 1.15)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("depth")
                .y_desc("Mrays/s")
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|e| e.to_string())?;
            for contender in ContenderKind::ALL {
                let points: Vec<(i32, f64)> = cases
                    .iter()
                    .filter_map(|c| {
                        let s = c.contender(contender)?.speed(kind, threads)?;
                        Some((i32::from(c.depth), s.mrays()))
                    })
                    .collect();
                if points.is_empty() {
                    continue;
                }
                let style = color(contender);
                chart
                    .draw_series(LineSeries::new(points.clone(), style.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(contender.label())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style.stroke_width(2)));
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, style.filled())))
                    .map_err(|e| e.to_string())?;
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    })
}

/// Build time (ms, log) against the solid's octree node count (log), every scene and
/// depth, one colour a contender.
pub fn build_plot(r: &MatrixResults, path: &Path) -> Result<()> {
    let points: Vec<(ContenderKind, f64, f64)> = r
        .cases
        .iter()
        .flat_map(|c| {
            c.contenders
                .iter()
                .filter(|x| x.skipped.is_none())
                .map(move |x| (x.kind, c.octree_nodes.max(1) as f64, x.build_ms.max(1e-3)))
        })
        .collect();
    let (x0, x1) = points.iter().fold((f64::INFINITY, 1.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (y0, y1) = points.iter().fold((f64::INFINITY, 1e-3f64), |(a, b), p| (a.min(p.2), b.max(p.2)));
    render_png(path, (900, 600), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption("Build time against octree node count", ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d((x0.min(x1) * 0.7..x1 * 1.4).log_scale(), (y0.min(y1) * 0.7..y1 * 1.4).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("octree nodes of the solid")
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_desc("build ms")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        for contender in ContenderKind::ALL {
            let mine: Vec<(f64, f64)> = points.iter().filter(|p| p.0 == contender).map(|p| (p.1, p.2)).collect();
            if mine.is_empty() {
                continue;
            }
            let style = color(contender);
            chart
                .draw_series(mine.iter().map(|&p| Circle::new(p, 5, style.filled())))
                .map_err(|e| e.to_string())?
                .label(contender.label())
                .legend(move |(x, y)| Circle::new((x + 8, y), 5, style.filled()));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| e.to_string())?;
        Ok(())
    })
}

/// A radiosity solution's convergence: the unshot fraction (log) against shots (left)
/// and against seconds (right); `history` and `seconds` as
/// `RadiosityStats::history` and `Radiosity::timeline` give them, `title` the caption.
pub fn convergence_plot(history: &[f64], seconds: &[f64], title: &str, path: &Path) -> Result<()> {
    let points: Vec<(f64, f64, f64)> = history
        .iter()
        .zip(seconds)
        .enumerate()
        .filter(|(_, (f, _))| **f > 0.0)
        .map(|(i, (f, s))| (i as f64, *s, *f))
        .collect();
    let low = points.iter().map(|p| p.2).fold(1.0, f64::min).max(1e-9);
    let high = points.iter().map(|p| p.2).fold(1e-9, f64::max).max(low * 10.0);
    let shots = points.last().map_or(1.0, |p| p.0.max(1.0));
    let time = points.last().map_or(1.0, |p| p.1.max(1e-3));
    render_png(path, (1200, 460), |root| {
        let panels = root.split_evenly((1, 2));
        for (panel, by_time) in panels.iter().zip([false, true]) {
            let (x_end, x_desc) = if by_time { (time, "seconds") } else { (shots, "shots") };
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{title}: unshot energy against {x_desc}"), ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(0.0..x_end * 1.02, (low * 0.7..high * 1.4).log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc("unshot / emitted")
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|e| e.to_string())?;
            let line = points.iter().map(|p| (if by_time { p.1 } else { p.0 }, p.2));
            chart
                .draw_series(LineSeries::new(line, RGBColor(200, 60, 20).stroke_width(2)))
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    })
}

/// One step of a large job at one depth: what [`large_plot`] draws.
#[derive(Clone, Debug, PartialEq)]
pub struct LargeStep {
    /// The octree depth.
    pub depth: u8,
    /// The step ("build body", "difference", ...).
    pub step: String,
    /// Wall time in seconds.
    pub seconds: f64,
    /// Peak resident memory in bytes.
    pub peak_bytes: f64,
}

/// Time and peak memory of each step against depth, both on log axes, with the
/// memory budget drawn as a line: two panels.
pub fn large_plot(steps: &[LargeStep], budget_bytes: f64, path: &Path) -> Result<()> {
    const MIB: f64 = 1024.0 * 1024.0;
    let mut names: Vec<&str> = Vec::new();
    for s in steps {
        if !names.contains(&s.step.as_str()) {
            names.push(&s.step);
        }
    }
    let (d0, d1) = steps.iter().fold((u8::MAX, 0), |(a, b), s| (a.min(s.depth), b.max(s.depth)));
    let palette = [RGBColor(200, 60, 20), RGBColor(30, 90, 200), RGBColor(20, 150, 90), RGBColor(120, 60, 180)];
    render_png(path, (1200, 460), |root| {
        let panels = root.split_evenly((1, 2));
        for (panel, memory) in panels.iter().zip([false, true]) {
            let value = |s: &LargeStep| if memory { s.peak_bytes / MIB } else { s.seconds };
            let low = steps.iter().map(value).fold(f64::INFINITY, f64::min).max(1e-3);
            let mut high = steps.iter().map(value).fold(0.0, f64::max).max(low * 10.0);
            if memory {
                high = high.max(budget_bytes / MIB);
            }
            let (caption, y_desc) =
                if memory { ("peak memory against depth", "MiB") } else { ("time against depth", "seconds") };
            let mut chart = ChartBuilder::on(panel)
                .caption(caption, ("sans-serif", 18))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(f64::from(d0) - 0.3..f64::from(d1) + 0.3, (low * 0.7..high * 1.5).log_scale())
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_desc("depth")
                .y_desc(y_desc)
                .x_labels(usize::from(d1 - d0) + 1)
                .x_label_formatter(&|x| format!("{x:.0}"))
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|e| e.to_string())?;
            for (name, color) in names.iter().zip(palette.iter().cycle()) {
                let points: Vec<(f64, f64)> =
                    steps.iter().filter(|s| s.step == *name).map(|s| (f64::from(s.depth), value(s))).collect();
                chart
                    .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(*name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
                chart
                    .draw_series(points.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| e.to_string())?;
            }
            if memory {
                let line = [(f64::from(d0) - 0.3, budget_bytes / MIB), (f64::from(d1) + 0.3, budget_bytes / MIB)];
                chart
                    .draw_series(LineSeries::new(line, BLACK.stroke_width(1)))
                    .map_err(|e| e.to_string())?
                    .label("budget")
                    .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(1)));
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperLeft)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font(("sans-serif", 13))
                .draw()
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    })
}

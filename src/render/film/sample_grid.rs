//! The sample grid of a picture: `spp x spp` samples a pixel, at the centres of their
//! strata, row-major from the top-left, in image coordinates `[-1, 1]^2` with y up.

/// The sample grid: `spp x spp` samples a pixel, at the centres of their strata.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleGrid {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples a pixel side.
    pub spp: u32,
}

impl SampleGrid {
    /// Samples a row.
    #[must_use]
    pub fn columns(&self) -> u32 {
        self.width * self.spp
    }

    /// Sample rows.
    #[must_use]
    pub fn rows(&self) -> u32 {
        self.height * self.spp
    }

    /// Image aspect, width / height.
    #[must_use]
    pub fn aspect(&self) -> f64 {
        f64::from(self.width) / f64::from(self.height)
    }

    /// Image point of sample `(col, row)` of the sample grid, `[-1, 1]^2`, y up.
    #[must_use]
    pub fn point(&self, col: u32, row: u32) -> (f64, f64) {
        let x = (f64::from(col) + 0.5) / f64::from(self.columns());
        let y = (f64::from(row) + 0.5) / f64::from(self.rows());
        (2.0 * x - 1.0, 1.0 - 2.0 * y)
    }

    /// The sample column (continuous) of image x in `[-1, 1]`.
    pub(crate) fn column_of(&self, x: f64) -> f64 {
        (x + 1.0) * 0.5 * f64::from(self.columns()) - 0.5
    }

    /// The sample row (continuous) of image y in `[-1, 1]`.
    pub(crate) fn row_of(&self, y: f64) -> f64 {
        (1.0 - y) * 0.5 * f64::from(self.rows()) - 0.5
    }
}

//! The scale of a shape drawn in a figure, recomputed from its layout: the vertical
//! exaggeration of a panel is its y-axis's length per metre over its x-axis's, from the axes
//! rectangle (pt) and the data ranges it draws; 1 is to scale.

use mass_spring_report::plot::Layout;

/// Length per data unit along x and along y of a panel, pt.
pub fn scales(layout: &Layout, panel: usize) -> (f64, f64) {
    let a = &layout.axes[panel];
    let ((x0, x1), (y0, y1)) = layout.ranges[panel];
    ((a.x1 - a.x0) / (x1 - x0), (a.y1 - a.y0) / (y1 - y0))
}

/// The vertical exaggeration of a panel: 1 when drawn to scale.
pub fn vertical_exaggeration(layout: &Layout, panel: usize) -> f64 {
    let (x, y) = scales(layout, panel);
    y / x
}

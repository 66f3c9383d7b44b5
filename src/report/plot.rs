//! The speed-against-error plot of a family (plotters): every variant a point labelled with
//! its name, the Pareto front drawn as a red line through its (filled) points, as SVG text
//! or an RGB buffer. Text is drawn with the Hack font bundled by `epaint_default_fonts`
//! (plotters' `ab_glyph` feature), so no system font is needed and the output depends on
//! the input alone.

use plotters::coord::Shift;
use plotters::prelude::*;

/// One point of the plot.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotPoint {
    /// Label drawn beside the point.
    pub label: String,
    /// Cost (x).
    pub cost: f64,
    /// Error (y).
    pub error: f64,
    /// Whether it is on the Pareto front.
    pub front: bool,
}

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotSpec {
    /// Title above the chart.
    pub title: String,
    /// Label of the x axis (the cost).
    pub x_label: String,
    /// Label of the y axis (the error).
    pub y_label: String,
    /// The points.
    pub points: Vec<PlotPoint>,
}

/// A plot could not be drawn (plotters' message).
#[derive(Debug, thiserror::Error)]
#[error("plot '{title}': {message}")]
pub struct PlotError {
    /// The plot's title.
    pub title: String,
    /// What failed.
    pub message: String,
}

/// The font family name the plots use.
const FONT: &str = "sans-serif";

/// Registers the bundled font with plotters, once.
fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TrueType font; a failure would only leave text undrawn.
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::HACK_REGULAR,
        );
    });
}

/// Draws `spec` on `root`.
fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    spec: &PlotSpec,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    // The cost axis is logarithmic: a family's costs span decades (the spectral film).
    let x_max = spec.points.iter().map(|p| p.cost).fold(0.0f64, f64::max);
    let x_min = spec
        .points
        .iter()
        .map(|p| p.cost)
        .filter(|c| *c > 0.0)
        .fold(f64::INFINITY, f64::min);
    let x_min = if x_min.is_finite() { x_min / 1.6 } else { 1.0 };
    let y_max = spec.points.iter().map(|p| p.error).fold(0.0f64, f64::max);
    let x_max = if x_max > 0.0 { x_max * 1.6 } else { 10.0 };
    // Below 0 a little, so that the reference (error 0) is inside the chart and drawn.
    let y_max = if y_max > 0.0 { y_max * 1.2 } else { 1.0 };
    let mut chart = ChartBuilder::on(&root)
        .caption(&spec.title, (FONT, 18))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x_min..x_max).log_scale(), -0.04 * y_max..y_max)?;
    chart
        .configure_mesh()
        .x_desc(&spec.x_label)
        .x_label_formatter(&|v| format!("{}", super::round_sig(*v, 2)))
        .y_label_formatter(&|v| format!("{}", super::round_sig(*v, 3)))
        .y_desc(&spec.y_label)
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    let mut front: Vec<(f64, f64)> = spec
        .points
        .iter()
        .filter(|p| p.front && p.cost > 0.0)
        .map(|p| (p.cost, p.error))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    chart.draw_series(LineSeries::new(front, RED.stroke_width(2)))?;
    chart.draw_series(spec.points.iter().map(|p| {
        let style = if p.front {
            RED.filled()
        } else {
            RGBColor(90, 90, 90).stroke_width(2)
        };
        EmptyElement::at((p.cost, p.error))
            + Circle::new((0, 0), 5, style)
            + Text::new(p.label.clone(), (8, -16), (FONT, 13))
    }))?;
    root.present()?;
    Ok(())
}

/// The plot as SVG text, `width × height` pixels.
pub fn svg(spec: &PlotSpec, width: u32, height: u32) -> Result<String, PlotError> {
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
        draw(root, spec).map_err(|e| PlotError {
            title: spec.title.clone(),
            message: e.to_string(),
        })?;
    }
    Ok(text)
}

/// The plot as 8-bit RGB pixels, row-major, `width × height`.
pub fn rgb(spec: &PlotSpec, width: u32, height: u32) -> Result<Vec<u8>, PlotError> {
    register_font();
    let mut pixels = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        draw(root, spec).map_err(|e| PlotError {
            title: spec.title.clone(),
            message: e.to_string(),
        })?;
    }
    Ok(pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> PlotSpec {
        PlotSpec {
            title: "t".into(),
            x_label: "cost".into(),
            y_label: "error".into(),
            points: vec![
                PlotPoint {
                    label: "ref".into(),
                    cost: 10.0,
                    error: 0.0,
                    front: true,
                },
                PlotPoint {
                    label: "fast".into(),
                    cost: 2.0,
                    error: 1.0,
                    front: true,
                },
            ],
        }
    }

    #[test]
    fn same_input_same_bytes_and_text_is_drawn() {
        let a = svg(&spec(), 320, 240).unwrap();
        assert_eq!(a, svg(&spec(), 320, 240).unwrap());
        assert!(a.contains("\nfast\n") && a.contains("\nref\n"), "{a}");
        let p = rgb(&spec(), 320, 240).unwrap();
        assert_eq!(p, rgb(&spec(), 320, 240).unwrap());
        // The front's red is drawn.
        assert!(p.chunks(3).any(|c| c == [255, 0, 0]));
    }
}

//! PNG line plots of validation curves (plotters rendering into memory, `png` encoding, written
//! atomically). The font (DejaVu Sans, free licence) is embedded so that plots render the same
//! on a machine without fonts.

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line through the points (a model or reference curve).
    Line,
    /// Filled circle markers only (simulated samples).
    Points,
}

/// One named series of (x, y) points.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Line or markers.
    pub style: Style,
}

/// A 2-D chart with axes labels and a legend.
#[derive(Clone, Debug)]
pub struct LinePlot {
    /// Caption above the chart.
    pub title: String,
    /// x-axis label (with unit).
    pub x_label: String,
    /// y-axis label (with unit).
    pub y_label: String,
    /// The series drawn, in order; colours cycle through a fixed palette.
    pub series: Vec<Series>,
}

/// Errors of [`LinePlot::write_png`]; they name the output file.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Nothing finite to draw.
    #[error("plot {path}: no finite points to draw")]
    Empty {
        /// The output file.
        path: String,
    },
    /// plotters failed to render.
    #[error("plot {path}: rendering failed: {msg}")]
    Render {
        /// The output file.
        path: String,
        /// plotters' message.
        msg: String,
    },
    /// Writing the file failed.
    #[error("plot {path}: {source}")]
    Io {
        /// The output file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}

const WIDTH: u32 = 800;
const HEIGHT: u32 = 560;
const PALETTE: [RGBColor; 5] = [
    RGBColor(0, 0, 0),
    RGBColor(200, 30, 30),
    RGBColor(30, 80, 200),
    RGBColor(20, 140, 40),
    RGBColor(150, 60, 160),
];

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // The embedded file is a valid TrueType font; registering it cannot fail at run time
        // except by a corrupted build, which the plot tests catch.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../assets/DejaVuSans.ttf"),
        );
    });
}

/// The range [lo, hi] of `values` padded by 5 % (or ±1 around a single value).
fn padded_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return None;
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        lo.abs().max(1.0)
    };
    Some((lo - pad, hi + pad))
}

impl LinePlot {
    /// Renders the chart and writes it to `path` as a PNG (800 × 560 px), atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let name = path.display().to_string();
        let pts = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let (x0, x1) =
            padded_range(pts().map(|p| p.0)).ok_or(PlotError::Empty { path: name.clone() })?;
        let (y0, y1) =
            padded_range(pts().map(|p| p.1)).ok_or(PlotError::Empty { path: name.clone() })?;
        register_font();
        let mut rgb = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
        self.render(&mut rgb, (x0, x1), (y0, y1))
            .map_err(|msg| PlotError::Render {
                path: name.clone(),
                msg,
            })?;
        atomic_write::write_atomically(path, |w| {
            let mut enc = png::Encoder::new(w, WIDTH, HEIGHT);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let mut writer = enc.write_header().map_err(std::io::Error::other)?;
            writer
                .write_image_data(&rgb)
                .map_err(std::io::Error::other)?;
            writer.finish().map_err(std::io::Error::other)
        })
        .map_err(|source| PlotError::Io { path: name, source })
    }

    fn render(&self, rgb: &mut [u8], x: (f64, f64), y: (f64, f64)) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Display| e.to_string();
        let root = BitMapBackend::with_buffer(rgb, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(x.0..x.1, y.0..y.1)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|x| e(&x))?;
        for (i, s) in self.series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            let anno = match s.style {
                Style::Line => chart
                    .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                    .map_err(|x| e(&x))?,
                Style::Points => chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                    .map_err(|x| e(&x))?,
            };
            anno.label(s.name.clone()).legend(move |(lx, ly)| {
                PathElement::new(vec![(lx, ly), (lx + 20, ly)], colour.stroke_width(2))
            });
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|x| e(&x))?;
        root.present().map_err(|x| e(&x))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
        let dec = png::Decoder::new(std::fs::File::open(path).unwrap());
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size()];
        let info = r.next_frame(&mut buf).unwrap();
        (info.width, info.height, buf)
    }

    #[test]
    fn writes_a_png_with_the_curve_drawn() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let plot = LinePlot {
            title: "y = x²".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![
                Series {
                    name: "curve".into(),
                    points: (0..=20)
                        .map(|i| (i as f64 / 20.0, (i as f64 / 20.0).powi(2)))
                        .collect(),
                    style: Style::Line,
                },
                Series {
                    name: "samples".into(),
                    points: vec![(0.5, 0.25)],
                    style: Style::Points,
                },
            ],
        };
        plot.write_png(&path).unwrap();
        let (w, h, rgb) = decode(&path);
        assert_eq!((w, h), (WIDTH, HEIGHT));
        // Red (second palette colour) pixels exist: the sample marker was drawn.
        let red = rgb
            .chunks(3)
            .filter(|p| p[0] > 180 && p[1] < 60 && p[2] < 60)
            .count();
        assert!(red > 10, "{red} red pixels");
        // Black curve pixels exist beyond the axes: more dark pixels than a blank chart has.
        let dark = rgb
            .chunks(3)
            .filter(|p| p[0] < 40 && p[1] < 40 && p[2] < 40)
            .count();
        assert!(dark > 1000, "{dark} dark pixels");
        // No temporary left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn refuses_a_plot_without_finite_points() {
        let plot = LinePlot {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series {
                name: "nan".into(),
                points: vec![(f64::NAN, 1.0)],
                style: Style::Line,
            }],
        };
        let err = plot.write_png(Path::new("/nonexistent/x.png")).unwrap_err();
        assert!(err.to_string().contains("no finite points"), "{err}");
    }
}

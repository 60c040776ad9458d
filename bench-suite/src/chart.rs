//! The log-scale bar chart of Table 1: one group of bars per model, one bar per
//! arithmetic, drawn with plotters into a pixel buffer and saved as PNG.

use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// One bar: seconds, and whether the render was stopped by the budget (then the bar is
/// a lower bound and drawn hollow).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bar {
    /// Seconds measured.
    pub seconds: f64,
    /// Whether the run was stopped by its time budget (the bar is a lower bound).
    pub stopped: bool,
}

/// Bars of one model, one per series (arithmetic); `None` where it was not run.
#[derive(Clone, Debug)]
pub struct Group {
    /// Group label (the model).
    pub label: String,
    /// One bar per arithmetic; `None` where it was not run.
    pub bars: Vec<Option<Bar>>,
}

/// Whether a font could be registered for text; without one the chart has no labels.
fn font_available() -> bool {
    static FONT: OnceLock<bool> = OnceLock::new();
    *FONT.get_or_init(|| {
        // Fonts are loaded at run time from the usual places: no font file is shipped.
        const CANDIDATES: &[&str] = &[
            "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/TTF/DejaVuSans.ttf",
            "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
            "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
            "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
            "/System/Library/Fonts/Supplemental/Arial.ttf",
            "C:\\Windows\\Fonts\\arial.ttf",
        ];
        for path in CANDIDATES {
            if let Ok(bytes) = std::fs::read(path) {
                // Registered once per process, so leaking the bytes is bounded.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
];

/// Draws the chart and writes it as a PNG to `path`. Returns whether text labels could
/// be drawn (a font was found).
pub fn bar_chart(
    path: &Path,
    title: &str,
    series: &[&str],
    groups: &[Group],
) -> Result<bool, String> {
    bar_chart_with_axis(path, title, "seconds (log scale)", series, groups)
}

/// [`bar_chart`] with another quantity on the log-scale y axis (`Bar::seconds` then
/// holds that quantity, e.g. evaluation counts), named by `y_desc`.
pub fn bar_chart_with_axis(
    path: &Path,
    title: &str,
    y_desc: &str,
    series: &[&str],
    groups: &[Group],
) -> Result<bool, String> {
    let (w, h) = (1200u32, 600u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let text = font_available();
    draw(&mut buf, (w, h), text, title, y_desc, series, groups)
        .map_err(|e| format!("chart: {e}"))?;
    let img = image::RgbImage::from_raw(w, h, buf).ok_or("chart: buffer size")?;
    img.save(path)
        .map_err(|e| format!("writing {}: {e}", path.display()))?;
    Ok(text)
}

fn draw(
    buf: &mut [u8],
    size: (u32, u32),
    text: bool,
    title: &str,
    y_desc: &str,
    series: &[&str],
    groups: &[Group],
) -> Result<(), Box<dyn std::error::Error>> {
    let root = BitMapBackend::with_buffer(buf, size).into_drawing_area();
    root.fill(&WHITE)?;
    let slots = series.len().max(1) as i32 + 1; // bars plus one gap per group
    let n = groups.len().max(1) as i32;
    let values = groups
        .iter()
        .flat_map(|g| g.bars.iter().flatten().map(|b| b.seconds))
        .filter(|s| s.is_finite() && *s > 0.0);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        (lo, hi) = (1e-3, 1.0);
    }
    // Whole decades around the data, so the log axis has labelled ticks.
    let y_lo = 10f64.powf((lo.log10() - 0.05).floor());
    let y_hi = 10f64.powf((hi.log10() + 0.05).ceil());

    let mut builder = ChartBuilder::on(&root);
    builder.margin(15);
    if text {
        builder
            .caption(title, ("sans-serif", 22))
            .x_label_area_size(70)
            .y_label_area_size(70);
    }
    let mut chart = builder.build_cartesian_2d(0..n * slots, (y_lo..y_hi).log_scale())?;
    let names: Vec<String> = groups.iter().map(|g| g.label.clone()).collect();
    let centre = (slots - 1) / 2;
    let fmt = move |x: &i32| -> String {
        if x.rem_euclid(slots) == centre {
            names.get((x / slots) as usize).cloned().unwrap_or_default()
        } else {
            String::new()
        }
    };
    let mut mesh = chart.configure_mesh();
    mesh.disable_x_mesh();
    if text {
        mesh.x_labels((n * slots + 1) as usize)
            .x_label_formatter(&fmt)
            .y_desc(y_desc)
            .y_label_formatter(&|y| format!("{y:.0e}"));
    } else {
        mesh.x_labels(0).y_labels(0);
    }
    mesh.draw()?;

    for (s, name) in series.iter().enumerate() {
        let colour = PALETTE[s % PALETTE.len()];
        let bars: Vec<_> = groups
            .iter()
            .enumerate()
            .filter_map(|(g, grp)| {
                let b = grp.bars.get(s).copied().flatten()?;
                let x0 = g as i32 * slots + s as i32;
                let top = b.seconds.clamp(y_lo, y_hi);
                let style = if b.stopped {
                    colour.stroke_width(2)
                } else {
                    colour.filled()
                };
                Some(Rectangle::new([(x0, y_lo), (x0 + 1, top)], style))
            })
            .collect();
        let anno = chart.draw_series(bars)?;
        if text {
            anno.label(*name).legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 12, y + 6)], colour.filled())
            });
        }
    }
    if text {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

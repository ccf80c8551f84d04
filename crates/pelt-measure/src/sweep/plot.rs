//! A sweep's pictures, drawn with plotters into memory with an embedded font (DejaVu Sans,
//! from the `dejavu` crate, registered with plotters' `ab_glyph` back end), so they come out
//! the same on a machine with no fonts installed: `sweep.png`, one panel per knob of time
//! against FLIP with the Pareto front drawn through its settings, and `contact.png`, every
//! setting's FLIP heat map with its label.

use std::path::Path;
use std::sync::Once;

use plotters::drawing::DrawingAreaErrorKind;
use plotters::prelude::*;

use super::{PlotError, ReadBackError, Row, Sweep, SweepError};
use pelt_preview::Image;

/// The family name the embedded font is registered under.
const FONT: &str = "dejavu-sans";

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TTF shipped by the crate; a failure would show as missing
        // text, which the sweep test's drawn-content check does not rely on.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// `e` while drawing the picture `what` (`sweep.png`, `contact.png`).
fn plot_error(what: &'static str) -> impl FnOnce(PlotError) -> SweepError {
    move |source| SweepError::Plot { what, source }
}

/// RGB bytes to an RGBA image.
fn image_of(rgb: &[u8], width: u32, height: u32) -> Image {
    Image {
        width,
        height,
        rgba: rgb
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
    }
}

/// The knobs in the order their first rows appear.
fn knobs(s: &Sweep) -> Vec<&str> {
    let mut out: Vec<&str> = Vec::new();
    for r in &s.rows {
        if !out.contains(&r.knob.as_str()) {
            out.push(&r.knob);
        }
    }
    out
}

/// One knob's panel.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    knob: &str,
    rows: &[&Row],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let xmax = rows.iter().map(|r| r.ms).fold(0.0, f64::max).max(1e-3) * 1.15;
    // The error axis spans the knob's errors with a margin (from 0 when they reach near it),
    // so a knob whose settings differ by little still shows its order.
    let emax = rows.iter().map(|r| f64::from(r.error)).fold(0.0, f64::max);
    let emin = rows.iter().map(|r| f64::from(r.error)).fold(emax, f64::min);
    let span = (emax - emin).max(emax * 0.02).max(1e-4);
    let ylo = if emin < 2.0 * span {
        0.0
    } else {
        emin - 0.4 * span
    };
    let yhi = emax + 0.4 * span;
    let against = rows.first().map_or("", |r| r.truth.name());
    let mut chart = ChartBuilder::on(area)
        .caption(format!("{knob} (against {against})"), (FONT, 15))
        .margin(8)
        .x_label_area_size(30)
        .y_label_area_size(48)
        .build_cartesian_2d(0.0..xmax, ylo..yhi)?;
    chart
        .configure_mesh()
        .x_desc("frame ms")
        .y_desc("FLIP")
        .label_style((FONT, 11))
        .axis_desc_style((FONT, 12))
        .x_labels(5)
        .y_labels(5)
        .light_line_style(WHITE)
        .draw()?;
    let mut front: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.pareto)
        .map(|r| (r.ms, f64::from(r.error)))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart.draw_series(LineSeries::new(front.clone(), RED.stroke_width(2)))?;
    chart.draw_series(
        front
            .iter()
            .map(|&p| Circle::new(p, 7, RED.stroke_width(2))),
    )?;
    chart.draw_series(rows.iter().map(|r| {
        let style = if r.default {
            BLACK.filled()
        } else {
            BLUE.filled()
        };
        Circle::new((r.ms, f64::from(r.error)), 4, style)
    }))?;
    chart.draw_series(rows.iter().map(|r| {
        EmptyElement::at((r.ms, f64::from(r.error)))
            + Text::new(r.value.clone(), (9, -14), (FONT, 11).into_font())
    }))?;
    Ok(())
}

/// `sweep.png`: one panel per knob, time against FLIP, the Pareto front in red, the default
/// setting black.
pub fn chart(s: &Sweep) -> Result<Image, SweepError> {
    register_font();
    let names = knobs(s);
    let cols = names.len().clamp(1, 3);
    let rows_n = names.len().div_ceil(cols).max(1);
    let (w, h) = (420 * cols as u32, 320 * rows_n as u32);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error("sweep.png"))?;
        let areas = root.split_evenly((rows_n, cols));
        for (area, knob) in areas.iter().zip(&names) {
            let rows: Vec<&Row> = s.rows.iter().filter(|r| r.knob == *knob).collect();
            panel(area, knob, &rows).map_err(plot_error("sweep.png"))?;
        }
        root.present().map_err(plot_error("sweep.png"))?;
    }
    Ok(image_of(&buf, w, h))
}

/// Width of one contact-sheet tile.
const TILE: u32 = 192;
/// Height of a tile's caption.
const CAPTION: u32 = 18;

/// `contact.png`: every setting's heat map (read back from `dir`), scaled to a tile, with
/// its label and error.
pub fn contact_sheet(s: &Sweep, dir: &Path) -> Result<Image, SweepError> {
    register_font();
    let (sw, sh) = s.size;
    let th = (TILE * sh / sw.max(1)).max(8);
    let cols = s.rows.len().clamp(1, 6) as u32;
    let rows_n = (s.rows.len() as u32).div_ceil(cols).max(1);
    let (w, h) = (cols * TILE, rows_n * (th + CAPTION));
    let mut buf = vec![255u8; (w * h * 3) as usize];
    for (i, r) in s.rows.iter().enumerate() {
        let heat = read_png(&dir.join(&r.heat))?;
        let tile = super::resize(&heat, TILE, th);
        let (x0, y0) = ((i as u32 % cols) * TILE, (i as u32 / cols) * (th + CAPTION));
        for y in 0..th {
            for x in 0..TILE {
                let p = tile.pixel(x, y);
                let o = (((y0 + y) * w + x0 + x) * 3) as usize;
                buf[o..o + 3].copy_from_slice(&p[..3]);
            }
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        for (i, r) in s.rows.iter().enumerate() {
            let (x0, y0) = ((i as u32 % cols) * TILE, (i as u32 / cols) * (th + CAPTION));
            let label = format!("{}={}  {:.3}", r.knob, r.value, r.error);
            root.draw(&Text::new(
                label,
                (x0 as i32 + 3, (y0 + th + 3) as i32),
                (FONT, 12).into_font(),
            ))
            .map_err(plot_error("contact.png"))?;
        }
        root.present().map_err(plot_error("contact.png"))?;
    }
    Ok(image_of(&buf, w, h))
}

/// Reads an 8-bit RGBA PNG this sweep wrote.
fn read_png(path: &Path) -> Result<Image, SweepError> {
    let fail = |source: ReadBackError| SweepError::ReadBack {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::open(path).map_err(|e| fail(e.into()))?;
    let mut dec = png::Decoder::new(std::io::BufReader::new(file));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| fail(e.into()))?;
    let mut data = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let info = reader.next_frame(&mut data).map_err(|e| fail(e.into()))?;
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
        return Err(fail(ReadBackError::NotRgba8));
    }
    data.truncate(info.buffer_size());
    Ok(Image {
        width: info.width,
        height: info.height,
        rgba: data,
    })
}

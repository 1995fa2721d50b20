//! A figure on paper: its format (SVG, PNG, PDF), its printed width, and the pixels of its layout.
//!
//! Every figure is laid out on a canvas of [`PX_PER_MM`] pixels per millimetre of the chosen
//! width, so its text (14.5 px, the smallest in any figure) prints at 14.5 / 5.56 = 2.61 mm
//! = 7.4 pt at every width: a narrower page reflows panels into fewer columns instead of
//! shrinking the text. The SVG says its size in millimetres; PNG and PDF are rendered from it
//! by resvg and svg2pdf with DejaVu Sans embedded (the same glyphs on every machine).

use std::sync::{Arc, OnceLock};

use resvg::usvg;

use super::FigureError;

/// Pixels of layout per millimetre of printed width: 1000 px at a 180 mm journal page.
pub const PX_PER_MM: f64 = 1000.0 / 180.0;

/// The widths a figure may be given, in millimetres.
pub const WIDTH_MM: std::ops::RangeInclusive<f64> = 60.0..=600.0;

/// The PNG resolutions accepted, in dots per inch.
pub const DPI: std::ops::RangeInclusive<f64> = 30.0..=1200.0;

/// The widest PNG, in pixels (a 600 mm page at 850 dpi).
pub const MAX_PNG_WIDTH: f64 = 20_000.0;

/// The most pixels a PNG may have (400 MB of RGBA while it is drawn).
pub const MAX_PNG_PIXELS: f64 = 1e8;

/// The file format of a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Format {
    /// Scalable vector graphics, text as text (fonts from the viewer).
    #[default]
    Svg,
    /// A raster image at the page's resolution.
    Png,
    /// A one-page PDF, the page as wide as the figure, text embedded (DejaVu Sans).
    Pdf,
}

impl std::str::FromStr for Format {
    type Err = super::FigureError;

    /// `svg`, `png` or `pdf`.
    fn from_str(name: &str) -> Result<Format, super::FigureError> {
        match name {
            "svg" => Ok(Format::Svg),
            "png" => Ok(Format::Png),
            "pdf" => Ok(Format::Pdf),
            other => Err(super::err(format!(
                "the figure format must be \"svg\", \"png\" or \"pdf\", not {}",
                crate::markup::clip(other)
            ))),
        }
    }
}

impl Format {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }
}

/// How a figure is put on paper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Page {
    /// The file format.
    pub format: Format,
    /// The printed width in millimetres (height follows the figure's layout).
    pub width_mm: f64,
    /// Resolution of a PNG, dots per inch.
    pub dpi: f64,
}

impl Default for Page {
    fn default() -> Self {
        Page {
            format: Format::Svg,
            width_mm: 180.0,
            dpi: 300.0,
        }
    }
}

impl Page {
    /// Refuse a width or resolution out of range (NaN included) before anything is drawn.
    pub fn check(&self) -> Result<(), FigureError> {
        if !WIDTH_MM.contains(&self.width_mm) {
            return Err(FigureError::Invalid(format!(
                "figure width {} mm is not in {}..={} mm",
                self.width_mm,
                WIDTH_MM.start(),
                WIDTH_MM.end()
            )));
        }
        if !DPI.contains(&self.dpi) {
            return Err(FigureError::Invalid(format!(
                "resolution {} dpi is not in {}..={} dpi",
                self.dpi,
                DPI.start(),
                DPI.end()
            )));
        }
        let pixels = self.width_mm / 25.4 * self.dpi;
        if self.format == Format::Png && pixels > MAX_PNG_WIDTH {
            return Err(FigureError::Invalid(format!(
                "a PNG {} mm wide at {} dpi would be {pixels:.0} pixels wide, over the \
                 {MAX_PNG_WIDTH} pixel limit: lower --dpi or --width",
                self.width_mm, self.dpi
            )));
        }
        Ok(())
    }

    /// The canvas width in pixels of layout.
    pub fn canvas_width(&self) -> u32 {
        (self.width_mm * PX_PER_MM).round() as u32
    }

    /// The figure `svg` (as the figures draw it, sized in pixels of layout) in this page's
    /// format and width.
    pub fn encode(&self, svg: &str) -> Result<Vec<u8>, FigureError> {
        self.check()?;
        let svg = in_millimetres(svg, self.width_mm)?;
        if self.format == Format::Svg {
            return Ok(svg.into_bytes());
        }
        let options = usvg::Options {
            font_family: FAMILY.into(),
            fontdb: fonts(),
            ..usvg::Options::default()
        };
        let tree = usvg::Tree::from_str(&svg, &options).map_err(super::err)?;
        match self.format {
            Format::Png => png(&tree, self.dpi),
            _ => svg2pdf::to_pdf(
                &tree,
                svg2pdf::ConversionOptions::default(),
                // usvg reads millimetres at 96 px per inch; at 96 dpi a PDF point is 1/72 inch.
                svg2pdf::PageOptions { dpi: 96.0 },
            )
            .map_err(|e| FigureError::Invalid(format!("cannot write the PDF: {e}"))),
        }
    }
}

const FAMILY: &str = "DejaVu Sans";

/// DejaVu Sans, loaded once, standing in for every generic family the figures name.
fn fonts() -> Arc<usvg::fontdb::Database> {
    static FONTS: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_font_data(dejavu::sans::regular().to_vec());
            db.set_sans_serif_family(FAMILY);
            db.set_serif_family(FAMILY);
            db.set_monospace_family(FAMILY);
            Arc::new(db)
        })
        .clone()
}

fn png(tree: &usvg::Tree, dpi: f64) -> Result<Vec<u8>, FigureError> {
    // The tree's size is in CSS pixels (96 per inch).
    let scale = (dpi / 96.0) as f32;
    let size = tree.size();
    let (w, h) = (
        (size.width() * scale).ceil() as u32,
        (size.height() * scale).ceil() as u32,
    );
    if w as f64 * h as f64 > MAX_PNG_PIXELS {
        return Err(FigureError::Invalid(format!(
            "a {w} × {h} pixel PNG is over the {MAX_PNG_PIXELS:e} pixel limit: lower --dpi"
        )));
    }
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| FigureError::Invalid(format!("cannot make a {w} × {h} image")))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        tree,
        resvg::tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| FigureError::Invalid(format!("cannot encode the PNG: {e}")))
}

/// The root `<svg width="W" height="H" viewBox=…>` of a figure given in millimetres, the
/// height in proportion (the view box keeps the pixels of layout).
fn in_millimetres(svg: &str, width_mm: f64) -> Result<String, FigureError> {
    let bad = || FigureError::Invalid("a figure without its <svg width height> header".into());
    let open = svg.find("<svg ").ok_or_else(bad)?;
    let close = open + svg[open..].find('>').ok_or_else(bad)?;
    let head = &svg[open..close];
    let number = |name: &str| -> Option<f64> {
        let at = head.find(&format!(" {name}=\""))? + name.len() + 3;
        head[at..].split('"').next()?.parse().ok()
    };
    let (w, h) = (
        number("width").ok_or_else(bad)?,
        number("height").ok_or_else(bad)?,
    );
    let height_mm = width_mm * h / w;
    let fmt = |v: f64| {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    let new_head = head
        .replacen(
            &format!(" width=\"{}\"", fmt(w)),
            &format!(" width=\"{}mm\"", fmt(width_mm)),
            1,
        )
        .replacen(
            &format!(" height=\"{}\"", fmt(h)),
            &format!(" height=\"{}mm\"", fmt(height_mm)),
            1,
        );
    Ok(format!("{}{}{}", &svg[..open], new_head, &svg[close..]))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SVG: &str = "<svg width=\"1000\" height=\"420\" viewBox=\"0 0 1000 420\" \
        xmlns=\"http://www.w3.org/2000/svg\">\n<text x=\"500\" y=\"200\" font-family=\"sans-serif\" \
        font-size=\"14.5\">θ ω Σ</text>\n</svg>\n";

    #[test]
    fn the_svg_says_its_size_in_millimetres() {
        let s = in_millimetres(SVG, 180.0).unwrap();
        assert!(s.starts_with("<svg width=\"180mm\" height=\"75.6mm\" viewBox=\"0 0 1000 420\""));
    }

    #[test]
    fn a_png_has_the_pixels_of_its_width_and_resolution_and_draws_text() {
        let page = Page {
            format: Format::Png,
            width_mm: 180.0,
            dpi: 254.0,
        };
        let bytes = page.encode(SVG).unwrap();
        let pixmap = resvg::tiny_skia::Pixmap::decode_png(&bytes).unwrap();
        // 180 mm at 254 dpi = 1800 px.
        assert_eq!((pixmap.width(), pixmap.height()), (1800, 756));
        let inked = pixmap.pixels().iter().filter(|p| p.red() < 128).count();
        assert!(inked > 100, "the text is drawn: {inked} dark pixels");
    }

    #[test]
    fn a_pdf_page_is_the_width_asked_for() {
        let page = Page {
            format: Format::Pdf,
            ..Page::default()
        };
        let bytes = page.encode(SVG).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        assert!(text.starts_with("%PDF-"));
        // 180 mm = 510.236 pt.
        assert!(text.contains("/MediaBox [0 0 510.23"), "{}", &text[..400]);
        assert!(text.contains("DejaVu"), "the font is embedded");
    }

    #[test]
    fn widths_and_resolutions_out_of_range_are_refused() {
        for (w, d) in [
            (f64::NAN, 300.0),
            (10.0, 300.0),
            (180.0, 0.0),
            (180.0, f64::INFINITY),
        ] {
            let page = Page {
                width_mm: w,
                dpi: d,
                ..Page::default()
            };
            assert!(page.check().is_err(), "{w} {d}");
        }
    }
}

//! Drawing a picture in a file format: SVG (text, drawn by [`SvgCanvas`]) or PNG (pixels,
//! drawn by [`RasterCanvas`], anti-aliased, and encoded by `png`).

use std::sync::OnceLock;

use anyhow::{anyhow, Context};
use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, DrawingAreaErrorKind, IntoDrawingArea};
use plotters::style::FontStyle;
use plotters_backend::DrawingBackend;

use super::raster::RasterCanvas;
use super::svg::{Layer, SvgCanvas};

/// The font family every text of the plots is set in.
pub const FONT: &str = "sans-serif";

/// DejaVu Sans, for the text of PNG plots and for measuring text in both formats (licence:
/// `fonts/LICENSE`).
pub(super) static FONT_FILE: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// The plots' file format.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Scalable vector graphics, its parts grouped by name.
    #[default]
    Svg,
    /// A bitmap.
    Png,
}

impl Format {
    /// The file name extension.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
        }
    }
}

/// The result of drawing on the backend `DB`.
pub type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A picture that draws itself on any plotters backend.
pub trait Picture {
    /// Its size in pixels.
    fn size(&self) -> (u32, u32);

    /// Draws it on `area`, naming what it draws through `layer`.
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB>;
}

/// Registers the bundled font under [`FONT`] (once; later calls return the first outcome).
pub fn register_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_FILE)
                .map_err(|_| "the bundled font cannot be read".to_string())
        })
        .clone()
        .map_err(|message| anyhow!(message))
}

/// `picture` drawn in `format`: the file's bytes.
pub fn render(picture: &impl Picture, format: Format) -> anyhow::Result<Vec<u8>> {
    register_font()?;
    let size = picture.size();
    let failed = |error: String| anyhow!("cannot draw the plot: {error}");
    match format {
        Format::Svg => {
            let mut text = String::new();
            {
                let layer = Layer::default();
                let area = SvgCanvas::new(&mut text, size, layer.clone()).into_drawing_area();
                picture
                    .draw(&area, &layer)
                    .and_then(|()| area.present())
                    .map_err(|e| failed(e.to_string()))?;
            }
            Ok(text.into_bytes())
        }
        Format::Png => {
            let mut pixels = vec![255; size.0 as usize * size.1 as usize * 3];
            {
                let font = ab_glyph::FontRef::try_from_slice(FONT_FILE)
                    .map_err(|_| anyhow!("the bundled font cannot be read"))?;
                let layer = Layer::default();
                let canvas = RasterCanvas::new(&mut pixels, size, layer.clone(), Some(font));
                let area = canvas.into_drawing_area();
                picture
                    .draw(&area, &layer)
                    .and_then(|()| area.present())
                    .map_err(|e| failed(e.to_string()))?;
            }
            encode_png(&pixels, size)
        }
    }
}

/// RGB pixels, row by row, as a PNG file.
fn encode_png(pixels: &[u8], (width, height): (u32, u32)) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .and_then(|mut writer| writer.write_image_data(pixels))
        .context("cannot encode the PNG")?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    /// A red diagonal on white, with a caption.
    struct Diagonal;

    impl Picture for Diagonal {
        fn size(&self) -> (u32, u32) {
            (120, 80)
        }
        fn draw<DB: DrawingBackend>(
            &self,
            area: &DrawingArea<DB, Shift>,
            layer: &Layer,
        ) -> Drawn<DB> {
            area.fill(&WHITE)?;
            layer.set("series", "diagonal");
            area.draw(&PathElement::new(
                vec![(0, 0), (119, 79)],
                RED.stroke_width(3),
            ))?;
            area.draw(&Text::new("τ∞", (60, 10), (FONT, 20).into_font()))
        }
    }

    #[test]
    fn a_png_decodes_to_the_picture() {
        let bytes = render(&Diagonal, Format::Png).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut pixels = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut pixels).unwrap();
        assert_eq!((info.width, info.height), (120, 80));
        assert_eq!(info.color_type, png::ColorType::Rgb);
        let at = |x: usize, y: usize| {
            let i = (y * 120 + x) * 3;
            (pixels[i], pixels[i + 1], pixels[i + 2])
        };
        assert_eq!(at(60, 40).0, 255, "on the diagonal");
        assert!(at(60, 40).1 < 40, "on the diagonal: {:?}", at(60, 40));
        assert_eq!(at(100, 10), (255, 255, 255), "off it");
        // The caption's glyphs are drawn: dark pixels around (60, 10), none in the corner.
        let dark = |x0: usize, y0: usize| {
            (x0..x0 + 20)
                .flat_map(|x| (y0..y0 + 15).map(move |y| (x, y)))
                .filter(|&(x, y)| at(x, y).0 < 128)
                .count()
        };
        assert!(dark(60, 3) > 10, "text is rasterised");
        assert_eq!(dark(2, 60), 0);
    }

    /// `text` drawn at (10, 10) in the font at size 100 as a PNG: the columns that have ink.
    fn ink_columns(text: &'static str) -> Vec<usize> {
        struct Word(&'static str);
        impl Picture for Word {
            fn size(&self) -> (u32, u32) {
                (400, 140)
            }
            fn draw<DB: DrawingBackend>(
                &self,
                area: &DrawingArea<DB, Shift>,
                _: &Layer,
            ) -> Drawn<DB> {
                area.fill(&WHITE)?;
                area.draw(&Text::new(self.0, (10, 10), (FONT, 100).into_font()))
            }
        }
        let bytes = render(&Word(text), Format::Png).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut pixels = vec![0; reader.output_buffer_size()];
        reader.next_frame(&mut pixels).unwrap();
        (0..400)
            .filter(|&x| (0..140).any(|y| pixels[3 * (y * 400 + x)] < 128))
            .collect()
    }

    /// Regression: plotters' bitmap text dropped each glyph's left side bearing and truncated
    /// its advance, so that glyphs sat unevenly ("constrai ned"). Each glyph's ink starts where
    /// the font puts it: the pen's position plus its side bearing.
    #[test]
    fn glyph_spacing_was_uneven_in_pngs() {
        let font = ab_glyph::FontRef::try_from_slice(FONT_FILE).unwrap();
        use ab_glyph::{Font, ScaleFont};
        let scale = super::super::raster::scale_for(&font, 100.0);
        let scaled = font.as_scaled(scale);
        let i = scaled.glyph_id('i');
        let (advance, bearing) = (scaled.h_advance(i), scaled.h_side_bearing(i));
        assert!(bearing > 3.0, "a glyph with a wide side bearing: {bearing}");
        let ink = ink_columns("ii");
        // Two runs of ink, each starting at the pen plus the bearing.
        let starts: Vec<usize> = ink
            .iter()
            .enumerate()
            .filter(|&(k, &x)| k == 0 || ink[k - 1] + 1 != x)
            .map(|(_, &x)| x)
            .collect();
        assert_eq!(starts.len(), 2, "{ink:?}");
        let expected = [10.0 + bearing, 10.0 + advance + bearing];
        for (start, expected) in starts.iter().zip(expected) {
            assert!(
                (*start as f32 - expected).abs() <= 1.0,
                "ink at {start}, the font says {expected}"
            );
        }
    }

    #[test]
    fn an_svg_groups_the_picture() {
        let text = String::from_utf8(render(&Diagonal, Format::Svg).unwrap()).unwrap();
        assert!(text.contains(r#"<g class="series" data-name="diagonal">"#));
        assert!(text.contains(">τ∞</text>"));
        assert_eq!(Format::Png.extension(), "png");
    }
}

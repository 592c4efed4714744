//! An SVG backend for plotters that groups what it draws: the drawing code names the layer it
//! draws (a series, the impact marks, the switch line…) and each layer becomes
//! `<g class="…" data-name="…">`, so a reader (or a test) finds the parts of a plot by name.

use std::cell::RefCell;
use std::fmt::Write as _;
use std::rc::Rc;

use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontStyle, FontTransform,
};

/// The layer being drawn, shared by the drawing code (which sets it) and the SVG canvas (which
/// groups the elements by it); other backends ignore it.
#[derive(Clone, Debug, Default)]
pub struct Layer(Rc<RefCell<Group>>, Rc<std::cell::Cell<Option<Clip>>>);

/// A rectangle of the canvas, in pixels: `(left, top)` included, `(right, bottom)` excluded.
pub type Clip = ((i32, i32), (i32, i32));

/// A group's class and name; an empty class is no group.
#[derive(Clone, Debug, Default, PartialEq)]
struct Group {
    class: String,
    name: String,
}

impl Layer {
    /// What is drawn next belongs to the layer `class` (`series`, `impacts`, …) named `name`
    /// (a series' name, or empty).
    pub fn set(&self, class: &str, name: &str) {
        *self.0.borrow_mut() = Group {
            class: class.to_string(),
            name: name.to_string(),
        };
    }

    /// What is drawn next is clipped to `area` (the plot, for the series), by the backends that
    /// clip (the PNG's); until [`Layer::unclip`].
    pub fn clip_to<DB: DrawingBackend>(
        &self,
        area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    ) {
        let (x, y) = area.get_base_pixel();
        let (w, h) = area.dim_in_pixel();
        self.1.set(Some(((x, y), (x + w as i32, y + h as i32))));
    }

    /// What is drawn next is not clipped.
    pub fn unclip(&self) {
        self.1.set(None);
    }

    /// The clip set, if any.
    pub fn clip(&self) -> Option<Clip> {
        self.1.get()
    }

    fn current(&self) -> Group {
        self.0.borrow().clone()
    }
}

/// Never fails: the SVG is written to a string.
type Never = std::convert::Infallible;

/// An SVG document drawn into a string; complete once presented (or dropped).
pub struct SvgCanvas<'a> {
    out: &'a mut String,
    size: (u32, u32),
    layer: Layer,
    open: Option<Group>,
    closed: bool,
}

impl<'a> SvgCanvas<'a> {
    /// A `width × height` canvas that writes into `out`, grouping by `layer`.
    pub fn new(out: &'a mut String, size: (u32, u32), layer: Layer) -> Self {
        out.clear();
        let _ = writeln!(
            out,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#,
            w = size.0,
            h = size.1
        );
        Self {
            out,
            size,
            layer,
            open: None,
            closed: false,
        }
    }

    /// Opens the current layer's group if it is not the open one; the buffer to write into.
    fn element(&mut self) -> &mut String {
        let group = self.layer.current();
        if self.open.as_ref() != Some(&group) {
            if self.open.take().is_some() {
                self.out.push_str("</g>\n");
            }
            if !group.class.is_empty() {
                let _ = writeln!(
                    self.out,
                    r#"<g class="{}" data-name="{}">"#,
                    escape(&group.class),
                    escape(&group.name)
                );
                self.open = Some(group);
            }
        }
        self.out
    }

    /// Writes the element `svg(paint)`, painted in `style` (filled or outlined), unless it is
    /// transparent.
    fn shape<S: BackendStyle>(
        &mut self,
        style: &S,
        fill: bool,
        svg: impl FnOnce(String) -> String,
    ) -> Result<(), DrawingErrorKind<Never>> {
        if style.color().alpha > 0.0 {
            let element = svg(paint(style, fill));
            let out = self.element();
            out.push_str(&element);
            out.push('\n');
        }
        Ok(())
    }

    fn close(&mut self) {
        if !self.closed {
            if self.open.take().is_some() {
                self.out.push_str("</g>\n");
            }
            self.out.push_str("</svg>\n");
            self.closed = true;
        }
    }
}

impl Drop for SvgCanvas<'_> {
    fn drop(&mut self) {
        self.close();
    }
}

/// `#rrggbb`.
fn hex(color: BackendColor) -> String {
    let (r, g, b) = color.rgb;
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// ` {what}-opacity="…"` for a translucent color, else nothing.
fn opacity(what: &str, color: BackendColor) -> String {
    if color.alpha < 1.0 {
        format!(r#" {what}-opacity="{:.3}""#, color.alpha.max(0.0))
    } else {
        String::new()
    }
}

/// The paint of a shape: filled, or outlined with the style's width.
fn paint<S: BackendStyle>(style: &S, fill: bool) -> String {
    let color = style.color();
    if fill {
        format!(r#"fill="{}"{}"#, hex(color), opacity("fill", color))
    } else {
        format!(
            r#"fill="none" stroke="{}" stroke-width="{}"{}"#,
            hex(color),
            style.stroke_width(),
            opacity("stroke", color)
        )
    }
}

/// `x,y x,y …`.
fn points(path: impl IntoIterator<Item = BackendCoord>) -> String {
    let mut text = String::new();
    for (x, y) in path {
        if !text.is_empty() {
            text.push(' ');
        }
        let _ = write!(text, "{x},{y}");
    }
    text
}

/// `text` with the characters XML reserves escaped, and those XML 1.0 does not allow at all
/// (control characters but tab and line breaks, U+FFFE and U+FFFF: a model named with one made
/// every plot malformed XML) replaced by U+FFFD.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if c < ' ' || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

impl DrawingBackend for SvgCanvas<'_> {
    type ErrorType = Never;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Never>> {
        Ok(())
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Never>> {
        self.close();
        Ok(())
    }

    fn draw_pixel(
        &mut self,
        (x, y): BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Never>> {
        self.shape(&color, true, |paint| {
            format!(r#"<rect x="{x}" y="{y}" width="1" height="1" {paint}/>"#)
        })
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        (x1, y1): BackendCoord,
        (x2, y2): BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Never>> {
        self.shape(style, false, |paint| {
            format!(r#"<line x1="{x1}" y1="{y1}" x2="{x2}" y2="{y2}" {paint}/>"#)
        })
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        (x0, y0): BackendCoord,
        (x1, y1): BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Never>> {
        let (x, y, w, h) = (x0.min(x1), y0.min(y1), (x1 - x0).abs(), (y1 - y0).abs());
        self.shape(style, fill, |paint| {
            format!(r#"<rect x="{x}" y="{y}" width="{w}" height="{h}" {paint}/>"#)
        })
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Never>> {
        self.shape(style, false, |paint| {
            let points = points(path);
            format!(r#"<polyline {paint} stroke-linejoin="round" points="{points}"/>"#)
        })
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        (x, y): BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Never>> {
        self.shape(style, fill, |paint| {
            format!(r#"<circle cx="{x}" cy="{y}" r="{radius}" {paint}/>"#)
        })
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vertices: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Never>> {
        self.shape(style, true, |paint| {
            format!(r#"<polygon {paint} points="{}"/>"#, points(vertices))
        })
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        (x, y): BackendCoord,
    ) -> Result<(), DrawingErrorKind<Never>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let anchor = match style.anchor().h_pos {
            HPos::Left => "start",
            HPos::Center => "middle",
            HPos::Right => "end",
        };
        // The shift from the anchor to the baseline, in the font's own units.
        let shift = match style.anchor().v_pos {
            VPos::Top => "0.8em",
            VPos::Center => "0.35em",
            VPos::Bottom => "-0.2em",
        };
        let weight = match style.style() {
            FontStyle::Bold => r#" font-weight="bold""#,
            FontStyle::Italic | FontStyle::Oblique => r#" font-style="italic""#,
            FontStyle::Normal => "",
        };
        let rotation = match style.transform() {
            FontTransform::Rotate90 => 90,
            FontTransform::Rotate180 => 180,
            FontTransform::Rotate270 => 270,
            FontTransform::None => 0,
        };
        let transform = if rotation == 0 {
            String::new()
        } else {
            format!(r#" transform="rotate({rotation}, {x}, {y})""#)
        };
        // plotters sizes a font by its line height, 1.24 em for the fonts it knows.
        let _ = writeln!(
            self.element(),
            r#"<text x="{x}" y="{y}" dy="{shift}" text-anchor="{anchor}" font-family="{}" font-size="{:.1}" fill="{}"{}{weight}{transform}>{}</text>"#,
            escape(style.family().as_str()),
            style.size() / 1.24,
            hex(color),
            opacity("fill", color),
            escape(text)
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    #[test]
    fn layers_become_named_groups() {
        let mut out = String::new();
        let layer = Layer::default();
        {
            let canvas = SvgCanvas::new(&mut out, (100, 50), layer.clone());
            let area = canvas.into_drawing_area();
            area.fill(&WHITE).unwrap();
            layer.set("series", "x<1>");
            area.draw(&PathElement::new(vec![(0, 0), (10, 20), (30, 5)], RED))
                .unwrap();
            area.draw(&Circle::new((5, 5), 3, BLUE.filled())).unwrap();
            layer.set("impacts", "");
            area.draw(&Circle::new((7, 8), 2, BLACK)).unwrap();
            area.present().unwrap();
        }
        assert!(out.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\""));
        assert!(out.ends_with("</g>\n</svg>\n"), "{out}");
        let series = out
            .find(r#"<g class="series" data-name="x&lt;1&gt;">"#)
            .unwrap();
        let impacts = out.find(r#"<g class="impacts" data-name="">"#).unwrap();
        let polyline = out.find("<polyline").unwrap();
        assert!(series < polyline && polyline < impacts, "{out}");
        assert!(out.contains(r##"stroke="#ff0000""##));
        assert!(out.contains(r#"points="0,0 10,20 30,5""#));
        assert!(out.contains(r##"<circle cx="5" cy="5" r="3" fill="#0000ff"/>"##));
        assert_eq!(out.matches("<g ").count(), out.matches("</g>").count());
        // The background, drawn before any layer was set, is outside every group.
        assert!(out.find("<rect").unwrap() < series);
    }

    #[test]
    fn text_is_escaped_and_placed() {
        crate::plot::canvas::register_font().unwrap();
        let mut out = String::new();
        {
            let canvas = SvgCanvas::new(&mut out, (200, 100), Layer::default());
            let area = canvas.into_drawing_area();
            let style = TextStyle::from(("sans-serif", 20).into_font())
                .pos(plotters::style::text_anchor::Pos::new(
                    HPos::Right,
                    VPos::Top,
                ))
                .transform(FontTransform::Rotate270);
            area.draw(&Text::new("τ∞ ≈ 2 & <x>", (50, 60), style))
                .unwrap();
        }
        assert!(out.contains(">τ∞ ≈ 2 &amp; &lt;x&gt;</text>"), "{out}");
        assert!(out.contains(r#"text-anchor="end""#), "{out}");
        assert!(out.contains(r#"transform="rotate(270, 50, 60)""#), "{out}");
        assert!(out.ends_with("</svg>\n"));
    }
}

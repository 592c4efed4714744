//! A JSON layout between compact and pretty: the outer levels indented one entry per line, the
//! inner ones on a single line, so that `summary.json` lists one event per line (pretty
//! printing spends a line on every number: 50 MB for 100 000 events).

use std::io;

use serde_json::ser::Formatter;

/// Indents containers up to `depth` levels deep (1: the top-level object's entries only);
/// deeper ones are written on one line, `{"q": [1, 2], "q_dot": [0, 0]}`.
pub struct Layout {
    depth: usize,
    level: usize,
    has_value: bool,
}

impl Layout {
    /// Entries of containers up to `depth` levels deep go on lines of their own.
    pub fn new(depth: usize) -> Self {
        Self {
            depth,
            level: 0,
            has_value: false,
        }
    }

    fn indented(&self) -> bool {
        self.level <= self.depth
    }

    fn separator<W: ?Sized + io::Write>(&self, writer: &mut W, first: bool) -> io::Result<()> {
        if self.indented() {
            writer.write_all(if first { b"\n" } else { b",\n" })?;
            newline_indent(writer, self.level)
        } else if first {
            Ok(())
        } else {
            writer.write_all(b", ")
        }
    }

    fn close<W: ?Sized + io::Write>(&mut self, writer: &mut W, bracket: &[u8]) -> io::Result<()> {
        let was_indented = self.indented();
        self.level -= 1;
        if was_indented && self.has_value {
            writer.write_all(b"\n")?;
            newline_indent(writer, self.level)?;
        }
        writer.write_all(bracket)
    }
}

fn newline_indent<W: ?Sized + io::Write>(writer: &mut W, level: usize) -> io::Result<()> {
    for _ in 0..level {
        writer.write_all(b"  ")?;
    }
    Ok(())
}

impl Formatter for Layout {
    fn begin_array<W: ?Sized + io::Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.level += 1;
        self.has_value = false;
        writer.write_all(b"[")
    }

    fn end_array<W: ?Sized + io::Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.close(writer, b"]")
    }

    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.separator(writer, first)
    }

    fn end_array_value<W: ?Sized + io::Write>(&mut self, _writer: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + io::Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.level += 1;
        self.has_value = false;
        writer.write_all(b"{")
    }

    fn end_object<W: ?Sized + io::Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.close(writer, b"}")
    }

    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.separator(writer, first)
    }

    fn begin_object_value<W: ?Sized + io::Write>(&mut self, writer: &mut W) -> io::Result<()> {
        writer.write_all(b": ")
    }

    fn end_object_value<W: ?Sized + io::Write>(&mut self, _writer: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

/// `value` as JSON in the [`Layout`] of `depth`.
pub fn to_writer<W: io::Write, T: serde::Serialize + ?Sized>(
    writer: W,
    value: &T,
    depth: usize,
) -> serde_json::Result<()> {
    let mut serializer = serde_json::Serializer::with_formatter(writer, Layout::new(depth));
    value.serialize(&mut serializer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn layout(value: &serde_json::Value, depth: usize) -> String {
        let mut out = Vec::new();
        to_writer(&mut out, value, depth).unwrap();
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn outer_levels_are_indented_inner_ones_inline() {
        let value = json!({
            "model": "ball",
            "empty": [],
            "none": {},
            "events": [{"t": 1.5, "q": [1.0, 2.0]}, {"t": 2.0, "q": []}],
            "final": {"q": [0.0]}
        });
        let text = layout(&value, 2);
        assert_eq!(
            text,
            "{\n  \"empty\": [],\n  \"events\": [\n    {\"q\": [1.0, 2.0], \"t\": 1.5},\n    \
             {\"q\": [], \"t\": 2.0}\n  ],\n  \"final\": {\n    \"q\": [0.0]\n  },\n  \
             \"model\": \"ball\",\n  \"none\": {}\n}"
        );
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, value);
        assert_eq!(
            layout(&value, 0),
            serde_json::to_string(&value)
                .unwrap()
                .replace(',', ", ")
                .replace(':', ": ")
        );
    }
}

//! Writing RGB frames as an animated GIF with the `gif` crate: one global palette made of the
//! animation's few colours blended into the white background (what antialiased lines and text
//! are made of), and each frame after the first only the rectangle that changed, its unchanged
//! pixels transparent over the frame before (which compresses to almost nothing).

use std::borrow::Cow;
use std::collections::HashMap;
use std::io::Write;

use anyhow::Context;
use gif::{DisposalMethod, Encoder, Frame, Repeat};

/// The palette index that stands for "unchanged" in every frame but the first.
const TRANSPARENT: u8 = 0;
/// The palette index of the background, white.
const WHITE: u8 = 1;
/// The blends of each colour with white, from the lightest to the colour itself.
const LEVELS: usize = 50;

/// An animated GIF being written to `W`.
pub struct GifWriter<W: Write> {
    encoder: Encoder<W>,
    width: u16,
    height: u16,
    /// Centiseconds each frame shows.
    delay: u16,
    palette: Vec<[u8; 3]>,
    /// The palette index of each colour met so far.
    nearest: HashMap<[u8; 3], u8>,
    /// The indices shown after the last frame written, `None` before the first.
    shown: Option<Vec<u8>>,
}

impl<W: Write> GifWriter<W> {
    /// A GIF of `width × height` frames, each shown `delay` centiseconds, looping forever,
    /// drawn in `colours` (at most 5) on white.
    pub fn new(
        out: W,
        (width, height): (u16, u16),
        delay: u16,
        colours: &[[u8; 3]],
    ) -> anyhow::Result<Self> {
        assert!(colours.len() * LEVELS + 2 <= 256, "too many colours");
        let mut palette = vec![[255, 0, 255], [255, 255, 255]];
        for colour in colours {
            for level in 1..=LEVELS {
                let a = level as f64 / LEVELS as f64;
                palette.push(colour.map(|c| (255.0 + a * (f64::from(c) - 255.0)).round() as u8));
            }
        }
        let flat: Vec<u8> = palette.iter().flatten().copied().collect();
        let mut encoder =
            Encoder::new(out, width, height, &flat).context("cannot start the GIF")?;
        encoder
            .set_repeat(Repeat::Infinite)
            .context("cannot start the GIF")?;
        Ok(Self {
            encoder,
            width,
            height,
            delay,
            palette,
            nearest: HashMap::new(),
            shown: None,
        })
    }

    /// The palette index nearest `rgb` (the transparent index excluded).
    fn index(&mut self, rgb: [u8; 3]) -> u8 {
        if rgb == [255, 255, 255] {
            return WHITE;
        }
        let palette = &self.palette;
        *self.nearest.entry(rgb).or_insert_with(|| {
            let distance = |p: &[u8; 3]| -> i32 {
                (0..3)
                    .map(|i| (i32::from(p[i]) - i32::from(rgb[i])).pow(2))
                    .sum()
            };
            (1..palette.len())
                .min_by_key(|&i| distance(&palette[i]))
                .expect("the palette has colours") as u8
        })
    }

    /// Adds a frame of RGB pixels, row by row.
    pub fn frame(&mut self, rgb: &[u8]) -> anyhow::Result<()> {
        let (w, h) = (usize::from(self.width), usize::from(self.height));
        assert_eq!(rgb.len(), w * h * 3, "a whole frame");
        let indices: Vec<u8> = rgb
            .chunks_exact(3)
            .map(|p| self.index([p[0], p[1], p[2]]))
            .collect();
        let mut frame = Frame {
            delay: self.delay,
            dispose: DisposalMethod::Keep,
            ..Frame::default()
        };
        match &self.shown {
            None => {
                frame.width = self.width;
                frame.height = self.height;
                frame.buffer = Cow::Borrowed(&indices);
                self.encoder
                    .write_frame(&frame)
                    .context("cannot write the GIF")?;
            }
            Some(shown) => {
                // The rectangle of the pixels that changed (one pixel when none did).
                let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
                for y in 0..h {
                    for x in 0..w {
                        if indices[y * w + x] != shown[y * w + x] {
                            x0 = x0.min(x);
                            y0 = y0.min(y);
                            x1 = x1.max(x + 1);
                            y1 = y1.max(y + 1);
                        }
                    }
                }
                if x0 >= x1 {
                    (x0, y0, x1, y1) = (0, 0, 1, 1);
                }
                let mut patch = Vec::with_capacity((x1 - x0) * (y1 - y0));
                for y in y0..y1 {
                    for x in x0..x1 {
                        let new = indices[y * w + x];
                        patch.push(if new == shown[y * w + x] {
                            TRANSPARENT
                        } else {
                            new
                        });
                    }
                }
                frame.left = x0 as u16;
                frame.top = y0 as u16;
                frame.width = (x1 - x0) as u16;
                frame.height = (y1 - y0) as u16;
                frame.transparent = Some(TRANSPARENT);
                frame.buffer = Cow::Owned(patch);
                self.encoder
                    .write_frame(&frame)
                    .context("cannot write the GIF")?;
            }
        }
        self.shown = Some(indices);
        Ok(())
    }

    /// Ends the GIF; the writer it was written to.
    pub fn finish(self) -> anyhow::Result<W> {
        self.encoder.into_inner().context("cannot finish the GIF")
    }
}

//! The file of a sweep (`zenosim sweep`, `zenosim merge`): CSV, one row per run, under a first
//! line that says which sweep it is and which shard:
//!
//! ```text
//! # zenosim sweep v1 zenosim=0.1.0 sweep=5f0c2a1e9b3d7c44 points=20 shard=1/3 model=bouncing-ball
//! index,e,h0,status,impacts,t_zeno,t_switch,t_final,final_y,final_y_dot,message
//! 0,0.3,0.5,finished,43,0.8...,0.8...,3,0,0,finished at t = 3 after 43 impacts and 1 Zeno point
//! ```
//!
//! `sweep` is a 64-bit FNV-1a hash of the model file's text and of the sweep (its axes and
//! their values, product or zipped, the settings changed): the shards of one sweep share it and
//! nothing else does, bar a collision. Numbers are in shortest round-trip form, `NaN` where
//! there is no value (pandas reads it as NaN: `pd.read_csv(path, skiprows=1)`).

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek, Write};
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};
use zenosim::ZenoStrategy;
use zenosim_runs::number::format_number;
use zenosim_runs::sweep::{Combine, Row, Shard, Sweep};

use crate::output::Record;

/// The first line's start, up to the format's version.
const PREFIX: &str = "# zenosim sweep v1 ";
/// The longest first line read (a model's name is short).
const MAX_FIRST_LINE: u64 = 4096;

/// Which sweep a file belongs to, and which part of it it holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Identity {
    /// The zenosim version that ran it.
    pub zenosim: String,
    /// The fingerprint of the model file and the sweep ([`fingerprint`]).
    pub sweep: u64,
    /// The number of points of the whole sweep.
    pub points: usize,
    /// The shard held.
    pub shard: Shard,
    /// The model's name (control characters written as spaces).
    pub model: String,
}

impl Identity {
    /// The identity of `shard` of `sweep`, run by this zenosim.
    pub fn of(sweep: &Sweep, shard: Shard) -> Self {
        Self {
            zenosim: env!("CARGO_PKG_VERSION").to_string(),
            sweep: fingerprint(sweep),
            points: sweep.points().len(),
            shard,
            model: sweep
                .model()
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect(),
        }
    }

    /// The first line of the file, without its newline.
    pub fn line(&self) -> String {
        format!(
            "{PREFIX}zenosim={} sweep={:016x} points={} shard={} model={}",
            self.zenosim, self.sweep, self.points, self.shard, self.model
        )
    }

    /// The identity a first line states, or what is wrong with it.
    pub fn parse(line: &str) -> Result<Self, String> {
        let rest = line
            .strip_prefix(PREFIX)
            .ok_or_else(|| format!("its first line is not `{}…`", PREFIX.trim_end()))?;
        let (fields, model) = rest
            .split_once(" model=")
            .ok_or("its first line names no model")?;
        let mut zenosim = None;
        let mut sweep = None;
        let mut points = None;
        let mut shard = None;
        for field in fields.split(' ') {
            let (key, value) = field
                .split_once('=')
                .ok_or_else(|| format!("`{field}` in its first line is not KEY=VALUE"))?;
            let bad = || format!("`{field}` in its first line is malformed");
            match key {
                "zenosim" => zenosim = Some(value.to_string()),
                "sweep" => sweep = Some(u64::from_str_radix(value, 16).map_err(|_| bad())?),
                "points" => points = Some(value.parse().map_err(|_| bad())?),
                "shard" => shard = Some(value.parse::<Shard>().map_err(|_| bad())?),
                _ => return Err(format!("`{key}` in its first line is unknown")),
            }
        }
        let missing = |key: &str| format!("its first line has no {key}=");
        Ok(Self {
            zenosim: zenosim.ok_or_else(|| missing("zenosim"))?,
            sweep: sweep.ok_or_else(|| missing("sweep"))?,
            points: points.ok_or_else(|| missing("points"))?,
            shard: shard.ok_or_else(|| missing("shard"))?,
            model: model.to_string(),
        })
    }

    /// This identity for the whole sweep (shard 1/1).
    pub fn whole(&self) -> Self {
        Self {
            shard: Shard::WHOLE,
            ..self.clone()
        }
    }
}

/// A 64-bit FNV-1a hash of the model file's text and of what the sweep does with it: the axes
/// and their values (exactly), product or zipped, and the settings it changes.
pub fn fingerprint(sweep: &Sweep) -> u64 {
    let mut spec = String::new();
    let combine = match sweep.points().combine() {
        Combine::Product => "product",
        Combine::Zip => "zip",
    };
    spec.push_str(combine);
    for axis in sweep.points().axes() {
        let values: Vec<String> = axis.values().iter().map(|v| format!("{v:?}")).collect();
        spec.push_str(&format!("\n{}={}", axis.name(), values.join(",")));
    }
    let s = sweep.settings();
    let zeno = match s.zeno {
        None => "file".to_string(),
        Some(ZenoStrategy::Auto) => "auto".to_string(),
        Some(ZenoStrategy::Off) => "off".to_string(),
        Some(ZenoStrategy::Epsilon(e)) => format!("{e:?}"),
    };
    let setting = |x: Option<f64>| x.map_or("file".to_string(), |x| format!("{x:?}"));
    spec.push_str(&format!(
        "\nt_end={} zeno={zeno} rtol={} atol={}",
        setting(s.t_end),
        setting(s.rtol),
        setting(s.atol)
    ));
    let hash = fnv1a(FNV_OFFSET, sweep.source().as_bytes());
    let hash = fnv1a(hash, &[0]);
    fnv1a(hash, spec.as_bytes())
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// FNV-1a over `bytes`, from `hash`.
fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(hash, |h, &b| (h ^ u64::from(b)).wrapping_mul(FNV_PRIME))
}

/// A CSV writer as the sweep files use it (the same for `sweep` and `merge`, so that merged
/// rows are written back byte for byte).
fn csv_writer<W: Write>(out: W) -> csv::Writer<W> {
    csv::WriterBuilder::new()
        .buffer_capacity(1 << 16)
        .from_writer(out)
}

/// Writes the file of `identity`: its first line, the header `columns`, and `rows`, as many of
/// them as fit in `max_bytes` (the first line and the header are always written). Returns the
/// writer and the number of rows written.
pub fn write<W: Write>(
    mut out: W,
    identity: &Identity,
    columns: &[String],
    rows: &[Row],
    max_bytes: u64,
) -> io::Result<(W, usize)> {
    let first = identity.line();
    writeln!(out, "{first}")?;
    // Each record is formatted on its own, so that its length is known before it is written.
    let record = Record::default();
    let mut csv = csv_writer(record.clone());
    csv.write_record(columns)?;
    csv.flush()?;
    let mut bytes = first.len() as u64 + 1 + record.len();
    record.take_into(&mut out)?;
    let mut number = String::new();
    let mut fields: Vec<String> = Vec::with_capacity(columns.len());
    for (written, row) in rows.iter().enumerate() {
        fields.clear();
        fields.push(row.index.to_string());
        let numbers = |fields: &mut Vec<String>, number: &mut String, xs: &[f64]| {
            for &x in xs {
                format_number(number, x);
                fields.push(number.clone());
            }
        };
        numbers(&mut fields, &mut number, &row.values);
        fields.push(row.status.word().to_string());
        fields.push(row.impacts.to_string());
        numbers(
            &mut fields,
            &mut number,
            &[row.t_zeno, row.t_switch, row.t_final],
        );
        numbers(&mut fields, &mut number, &row.q);
        numbers(&mut fields, &mut number, &row.q_dot);
        fields.push(row.message.clone());
        csv.write_record(&fields)?;
        csv.flush()?;
        bytes += record.len();
        if bytes > max_bytes {
            return Ok((out, written));
        }
        record.take_into(&mut out)?;
    }
    Ok((out, rows.len()))
}

/// The fewest bytes the file of `identity` can take with `points` rows of `columns`: its first
/// line, the header, and rows of one character a field (no value can be written shorter).
pub fn least_size(identity: &Identity, columns: &[String], points: usize) -> u64 {
    let first = identity.line().len() as u64 + 1;
    let header: u64 = columns.iter().map(|c| c.len() as u64 + 1).sum();
    // Each field a character and its comma (the last its newline); the status at least
    // `failed` (5 more), the message at least `failed: …` (7 more).
    let row = 2 * columns.len() as u64 + 12;
    first + header + row.saturating_mul(points as u64)
}

/// A sweep file open for reading, its first line and header read.
pub struct Part {
    /// Its path.
    pub path: PathBuf,
    /// What its first line says.
    pub identity: Identity,
    /// Its header.
    pub header: csv::ByteRecord,
    reader: csv::Reader<BufReader<File>>,
}

impl Part {
    /// Opens `path` and reads its first line and header; every error names the file.
    pub fn open(path: &Path) -> anyhow::Result<Self> {
        let display = path.display();
        let mut file = File::open(path).with_context(|| format!("cannot read {display}"))?;
        // Every row ends with a newline: a file that does not was cut short (a copy that did not
        // finish), and its last row may be cut inside a field.
        let ends_in_newline = file.seek(io::SeekFrom::End(-1)).is_ok() && {
            let mut last = [0u8];
            file.read_exact(&mut last).is_ok() && last[0] == b'\n'
        };
        if !ends_in_newline {
            return Err(anyhow!(
                "{display}: does not end with a newline: the file is cut short (a copy or a run \
                 that did not finish); write it again"
            ));
        }
        file.seek(io::SeekFrom::Start(0))
            .with_context(|| format!("cannot read {display}"))?;
        let mut reader = BufReader::new(file);
        let mut first = String::new();
        (&mut reader)
            .take(MAX_FIRST_LINE)
            .read_line(&mut first)
            .map_err(|error| match error.kind() {
                io::ErrorKind::InvalidData => {
                    anyhow!("{display}: not a zenosim sweep file (it is not text)")
                }
                _ => anyhow!("cannot read {display}: {error}"),
            })?;
        let identity = Identity::parse(first.trim_end_matches(['\n', '\r'])).map_err(|why| {
            anyhow!(
                "{display}: not a zenosim sweep file: {why} (write the parts with `zenosim \
                 sweep --shard K/N`)"
            )
        })?;
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .from_reader(reader);
        let header = reader
            .byte_headers()
            .map_err(|error| anyhow!("{display}:2: cannot read the header: {error}"))?
            .clone();
        Ok(Self {
            path: path.to_path_buf(),
            identity,
            header,
            reader,
        })
    }

    /// Reads the next row into `record`; false at the end of the file.
    pub fn next(&mut self, record: &mut csv::ByteRecord) -> anyhow::Result<bool> {
        let line = self.line();
        self.reader
            .read_byte_record(record)
            .map_err(|error| anyhow!("{}:{line}: a malformed row: {error}", self.path.display()))
    }

    /// The line of the file the next row starts on (the first line counted).
    pub fn line(&self) -> u64 {
        self.reader.position().line() + 1
    }
}

/// Writes a header and rows read from parts, exactly as [`write`] wrote them.
pub struct Rewriter<W: Write> {
    csv: csv::Writer<W>,
}

impl<W: Write> Rewriter<W> {
    /// Starts the file of `identity` with `header`.
    pub fn new(mut out: W, identity: &Identity, header: &csv::ByteRecord) -> io::Result<Self> {
        writeln!(out, "{}", identity.line())?;
        let mut csv = csv_writer(out);
        csv.write_byte_record(header)?;
        Ok(Self { csv })
    }

    /// Writes `record`.
    pub fn row(&mut self, record: &csv::ByteRecord) -> io::Result<()> {
        Ok(self.csv.write_byte_record(record)?)
    }

    /// Flushes the rows and returns the underlying writer.
    pub fn finish(self) -> io::Result<W> {
        self.csv.into_inner().map_err(|error| error.into_error())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_has_its_reference_values() {
        // The FNV test vectors for FNV-1a, 64 bits.
        assert_eq!(fnv1a(FNV_OFFSET, b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a(FNV_OFFSET, b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a(FNV_OFFSET, b"foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn identities_read_back() {
        let identity = Identity {
            zenosim: "0.1.0".to_string(),
            sweep: 0x00ab_cdef_0123_4567,
            points: 20,
            shard: Shard::new(2, 3).unwrap(),
            model: "a ball = fun".to_string(),
        };
        let line = identity.line();
        assert_eq!(
            line,
            "# zenosim sweep v1 zenosim=0.1.0 sweep=00abcdef01234567 points=20 shard=2/3 \
             model=a ball = fun"
        );
        assert_eq!(Identity::parse(&line).unwrap(), identity);
        assert_eq!(identity.whole().shard, Shard::WHOLE);
        for (bad, why) in [
            ("t,mode,x", "is not `# zenosim sweep v1…`"),
            ("# zenosim sweep v1 zenosim=0.1.0", "names no model"),
            (
                "# zenosim sweep v1 zenosim=0.1.0 sweep=xyz points=2 shard=1/1 model=m",
                "`sweep=xyz` in its first line is malformed",
            ),
            (
                "# zenosim sweep v1 zenosim=0.1.0 points=2 shard=1/1 model=m",
                "no sweep=",
            ),
        ] {
            let error = Identity::parse(bad).unwrap_err();
            assert!(error.contains(why), "{bad}: {error}");
        }
    }
}

//! Reading OpenFOAM files: the `FoamFile` header, dictionaries and lists, in ASCII and in
//! binary (`format binary;`, contiguous lists stored as raw little-endian bytes between the
//! parentheses), plain or gzipped.
//!
//! Untrusted input: every declared count is checked against the bytes that remain before
//! anything is allocated, counts are checked for overflow, integers must parse as integers and
//! nesting is bounded. Errors name the file, the line and the byte offset.

use super::error::FoamError;
use flate2::read::GzDecoder;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest decompressed size accepted for one gzipped file whatever it holds (the cap for a
/// file of unknown content; a file whose size the reader can bound from its declared counts is
/// stopped much earlier).
pub const MAX_INFLATED_BYTES: u64 = 1 << 33;
/// Most inflated bytes per compressed byte accepted for a gzipped file read before any count
/// is known (`faces`). Deflate reaches 1032 on repeated bytes, but a mesh's label lists hold
/// distinct faces: the shipped cases' `faces.gz` and `owner.gz` inflate 2-7 fold, and the most
/// regular lists there are (a structured hex mesh's faces, `4(i i+1 i+101 i+100)`, 6.1 fold in
/// ASCII and 3.3 in binary; a counting sequence 3.6 fold) stay under 7. 32 leaves a factor
/// 4.5 above them.
pub const MAX_DEFLATE_RATIO: u64 = 32;
/// Deepest nesting of parentheses and dictionaries accepted in generic values.
const MAX_DEPTH: usize = 64;
/// Bytes allowed for everything in a file that is not a counted entry: the banner comment,
/// the `FoamFile` header (under 1 KiB as OpenFOAM writes them), the keys around the lists.
/// The header must also fit in this many inflated bytes, so a gzip of zeros or garbage is
/// refused after inflating this much.
pub const HEADER_BYTES: u64 = 1 << 16;
/// Most bytes one number takes in ASCII: OpenFOAM writes at most 17 significant digits,
/// `-1.2345678901234567e-308` is 24 bytes and a label at most 20 (`-9223372036854775808`);
/// 32 leaves room for a separator and for writers that indent.
const NUMBER_BYTES: u64 = 32;
/// Bytes an entry takes beyond its numbers: `(`, `)`, a count prefix such as `4` of a face,
/// a newline.
const ENTRY_BYTES: u64 = 8;

/// The most a gzipped file may inflate to, with the reason (for the error). Binary lists take
/// 4 or 8 bytes a number, fewer than ASCII: an ASCII bound holds for both.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Limit {
    /// Most inflated bytes accepted.
    pub bytes: u64,
    /// Where the bound comes from, with its numbers.
    pub basis: String,
}

impl Limit {
    /// No count known yet (the first file a reader opens): `path.gz` may inflate to
    /// [`MAX_DEFLATE_RATIO`] times its compressed size, plus [`HEADER_BYTES`], capped at
    /// [`MAX_INFLATED_BYTES`]. Without `path.gz` the bound is never used (a plain file is
    /// read as it is, a missing one refused) and is that cap.
    pub fn deflated(path: &Path, what: &str) -> Self {
        let mut gz = path.as_os_str().to_owned();
        gz.push(".gz");
        let Ok(compressed) = std::fs::metadata(&gz).map(|m| m.len()) else {
            return Self {
                bytes: MAX_INFLATED_BYTES,
                basis: "the cap for a file of unknown size".into(),
            };
        };
        let bytes = compressed
            .saturating_mul(MAX_DEFLATE_RATIO)
            .saturating_add(HEADER_BYTES)
            .min(MAX_INFLATED_BYTES);
        Self {
            bytes,
            basis: format!(
                "{compressed} compressed bytes of {what} at {MAX_DEFLATE_RATIO} inflated bytes each \
                 (mesh lists deflate 2-7 fold), {HEADER_BYTES} for the header"
            ),
        }
    }

    /// At most `count` entries of `comps` numbers each (`what` names them), in ASCII: each
    /// entry at most `comps * NUMBER_BYTES + ENTRY_BYTES` bytes, plus [`HEADER_BYTES`] and
    /// `extra` bytes (`extra_why` says for what). Capped at [`MAX_INFLATED_BYTES`].
    pub fn entries(count: usize, comps: usize, what: &str, extra: u64, extra_why: &str) -> Self {
        Self::sized(count, comps as u64 * NUMBER_BYTES + ENTRY_BYTES, what, extra, extra_why)
    }

    /// At most `count` entries of at most `per` bytes each, plus [`HEADER_BYTES`] and `extra`
    /// bytes (`extra_why` says for what). Capped at [`MAX_INFLATED_BYTES`].
    pub fn sized(count: usize, per: u64, what: &str, extra: u64, extra_why: &str) -> Self {
        let bytes = (count as u64)
            .saturating_mul(per)
            .saturating_add(HEADER_BYTES)
            .saturating_add(extra)
            .min(MAX_INFLATED_BYTES);
        let extra = if extra > 0 {
            format!(", {extra} for {extra_why}")
        } else {
            String::new()
        };
        Self {
            bytes,
            basis: format!("{count} {what} at {per} bytes each, {HEADER_BYTES} for the header{extra}"),
        }
    }
}

/// Read `path`, or `path.gz` inflated, into memory. Returns the name used in messages.
///
/// A gzipped file is inflated only as far as it can be legitimate: its header must parse within
/// the first [`HEADER_BYTES`] and the whole within `limit.bytes` (what the entries the caller
/// expects can take), so a small gzip of zeros or of a huge list stops after at most
/// `limit.bytes + 1` inflated bytes, not [`MAX_INFLATED_BYTES`].
pub(crate) fn read_file(path: &Path, limit: Limit) -> Result<(String, Vec<u8>), FoamError> {
    let io = |p: &Path, source| FoamError::Io {
        path: p.display().to_string(),
        source,
    };
    if path.is_file() {
        let bytes = std::fs::read(path).map_err(|e| io(path, e))?;
        return Ok((path.display().to_string(), bytes));
    }
    let mut gz = path.as_os_str().to_owned();
    gz.push(".gz");
    let gz = PathBuf::from(gz);
    if !gz.is_file() {
        return Err(FoamError::Missing {
            path: path.display().to_string(),
        });
    }
    let shown = gz.display().to_string();
    let file = std::fs::File::open(&gz).map_err(|e| io(&gz, e))?;
    let mut inflate = GzDecoder::new(file);
    let mut bytes = Vec::new();
    (&mut inflate)
        .take(HEADER_BYTES)
        .read_to_end(&mut bytes)
        .map_err(|e| io(&gz, e))?;
    Parser::new(&shown, &bytes).header()?;
    inflate
        .take((limit.bytes + 1).saturating_sub(bytes.len() as u64))
        .read_to_end(&mut bytes)
        .map_err(|e| io(&gz, e))?;
    if bytes.len() as u64 > limit.bytes {
        return Err(FoamError::Inflated {
            path: shown,
            limit: limit.bytes,
            basis: limit.basis,
        });
    }
    Ok((shown, bytes))
}

/// One lexical token. Numbers are words (they are told apart where a number is expected).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Tok<'a> {
    /// One of `; { } ( ) [ ]`.
    Punct(u8),
    /// A word or number.
    Word(&'a str),
    /// A double-quoted string (without quotes).
    Str(&'a str),
    /// End of input.
    Eof,
}

/// A generic value inside a dictionary entry.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    /// A word or number.
    Word(String),
    /// A quoted string.
    Str(String),
    /// A parenthesised list of values, e.g. `(1 0 0)`.
    List(Vec<Value>),
    /// A dimension set `[0 1 -1 0 0 0 0]` (kept as text; not used).
    Dims,
    /// A typed numeric list `List<T> n (...)` or `List<T> n {v}`.
    Numbers(Numbers),
}

/// A numeric list: `count` elements of `comps` components. `data` holds all of them, or a
/// single element when the file used the uniform form `n{v}` (expanded only once the count has
/// been checked against the mesh).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Numbers {
    /// Components per element (1 scalar, 3 vector, 6 symmTensor, 9 tensor).
    pub comps: usize,
    /// Declared number of elements.
    pub count: usize,
    /// `count * comps` values, or `comps` values for the uniform form.
    pub data: Vec<f64>,
    /// Byte offset where the list starts (for messages).
    pub offset: usize,
}

/// A dictionary entry: a sub-dictionary or a stream of values up to `;`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Entry {
    /// `key { ... }`.
    Dict(Dict),
    /// `key v1 v2 ... ;`.
    Values(Vec<Value>),
}

/// Dictionary entries in file order, each with the byte offset of its key.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Dict {
    /// (key, entry, offset).
    pub entries: Vec<(String, Entry, usize)>,
    /// Offset of the opening brace (or 0 at top level).
    pub offset: usize,
}

impl Dict {
    /// Entry `key`; the last one wins, as in OpenFOAM.
    pub fn get(&self, key: &str) -> Option<(&Entry, usize)> {
        self.entries
            .iter()
            .rev()
            .find(|(k, _, _)| k == key)
            .map(|(_, e, o)| (e, *o))
    }

    /// The single word of entry `key` (e.g. `type`), if present and of that form.
    pub fn word(&self, key: &str) -> Option<&str> {
        match self.get(key)? {
            (Entry::Values(v), _) => match v.as_slice() {
                [Value::Word(w)] | [Value::Str(w)] => Some(w),
                _ => None,
            },
            _ => None,
        }
    }
}

/// The `FoamFile` header.
#[derive(Debug, Clone)]
pub(crate) struct Header {
    /// `class` (e.g. `faceCompactList`, `volVectorField`).
    pub class: String,
}

/// Cursor over one file's bytes.
pub(crate) struct Parser<'a> {
    path: &'a str,
    text: &'a [u8],
    pos: usize,
    binary: bool,
    label_bytes: usize,
    scalar_bytes: usize,
}

fn is_delim(b: u8) -> bool {
    b.is_ascii_whitespace() || matches!(b, b';' | b'{' | b'}' | b'(' | b')' | b'[' | b']' | b'"')
}

impl<'a> Parser<'a> {
    /// Parser over `text`; call [`Parser::header`] first.
    pub fn new(path: &'a str, text: &'a [u8]) -> Self {
        Self {
            path,
            text,
            pos: 0,
            binary: false,
            label_bytes: 4,
            scalar_bytes: 8,
        }
    }

    /// Current byte offset.
    pub fn offset(&self) -> usize {
        self.pos
    }

    /// A [`FoamError::Malformed`] at `offset`.
    pub fn error_at(&self, offset: usize, reason: impl Into<String>) -> FoamError {
        let offset = offset.min(self.text.len());
        let line = 1 + self.text[..offset].iter().filter(|&&b| b == b'\n').count();
        FoamError::Malformed {
            path: self.path.to_string(),
            line,
            offset,
            reason: reason.into(),
        }
    }

    fn skip_space(&mut self) -> Result<(), FoamError> {
        loop {
            while self.pos < self.text.len() && self.text[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let rest = &self.text[self.pos..];
            if rest.starts_with(b"//") {
                let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
                self.pos += end;
            } else if rest.starts_with(b"/*") {
                let end = rest
                    .windows(2)
                    .skip(2)
                    .position(|w| w == b"*/")
                    .ok_or_else(|| self.error_at(self.pos, "unterminated /* comment"))?;
                self.pos += end + 4;
            } else {
                return Ok(());
            }
        }
    }

    /// Next token.
    pub fn token(&mut self) -> Result<Tok<'a>, FoamError> {
        self.skip_space()?;
        let text = self.text;
        let Some(&b) = text.get(self.pos) else {
            return Ok(Tok::Eof);
        };
        let start = self.pos;
        if matches!(b, b';' | b'{' | b'}' | b'(' | b')' | b'[' | b']') {
            self.pos += 1;
            return Ok(Tok::Punct(b));
        }
        if b == b'"' {
            let len = text[start + 1..]
                .iter()
                .position(|&c| c == b'"')
                .ok_or_else(|| self.error_at(start, "unterminated string"))?;
            self.pos = start + len + 2;
            let s = std::str::from_utf8(&text[start + 1..start + 1 + len])
                .map_err(|_| self.error_at(start, "string is not UTF-8"))?;
            return Ok(Tok::Str(s));
        }
        let len = text[start..]
            .iter()
            .position(|&c| is_delim(c))
            .unwrap_or(text.len() - start);
        self.pos = start + len;
        let w = std::str::from_utf8(&text[start..start + len])
            .map_err(|_| self.error_at(start, "word is not UTF-8 text (binary data where text was expected?)"))?;
        Ok(Tok::Word(w))
    }

    fn peek(&mut self) -> Result<Tok<'a>, FoamError> {
        let pos = self.pos;
        let tok = self.token();
        self.pos = pos;
        tok
    }

    /// Consume punctuation `p` or fail.
    pub fn expect(&mut self, p: u8) -> Result<(), FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Punct(q) if q == p => Ok(()),
            other => Err(self.error_at(at, format!("expected `{}`, found {}", p as char, describe(other)))),
        }
    }

    fn skip_then_offset(&mut self) -> Result<usize, FoamError> {
        self.skip_space()?;
        Ok(self.pos)
    }

    /// A non-negative integer (a count or a label).
    pub fn count(&mut self) -> Result<usize, FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Word(w) => w
                .parse::<usize>()
                .map_err(|_| self.error_at(at, format!("expected a non-negative integer, found `{w}`"))),
            other => Err(self.error_at(
                at,
                format!("expected a non-negative integer, found {}", describe(other)),
            )),
        }
    }

    /// Parse the `FoamFile { ... }` header and set the binary format from it.
    pub fn header(&mut self) -> Result<Header, FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Word("FoamFile") => {}
            other => {
                return Err(self.error_at(at, format!("expected the `FoamFile` header, found {}", describe(other))));
            }
        }
        self.expect(b'{')?;
        let dict = self.dict_body(at, 1)?;
        let format = dict.word("format").unwrap_or("ascii");
        self.binary = match format {
            "ascii" => false,
            "binary" => true,
            other => return Err(self.error_at(at, format!("unknown format `{other}`"))),
        };
        if let Some(arch) = dict.word("arch") {
            for part in arch.split(';').map(str::trim) {
                let bits = |v: &str| v.parse::<usize>().ok().filter(|b| matches!(b, 32 | 64));
                if let Some(v) = part.strip_prefix("label=") {
                    self.label_bytes =
                        bits(v).ok_or_else(|| self.error_at(at, format!("unsupported label size `{v}`")))? / 8;
                } else if let Some(v) = part.strip_prefix("scalar=") {
                    self.scalar_bytes =
                        bits(v).ok_or_else(|| self.error_at(at, format!("unsupported scalar size `{v}`")))? / 8;
                } else if part == "MSB" {
                    return Err(self.error_at(at, "big-endian (MSB) binary files are not supported"));
                }
            }
        }
        let class = dict
            .word("class")
            .ok_or_else(|| self.error_at(at, "header has no `class`"))?
            .to_string();
        Ok(Header { class })
    }

    /// Entries up to the matching `}` (nested) or the end of the file (`depth == 0`).
    pub fn dict_body(&mut self, offset: usize, depth: usize) -> Result<Dict, FoamError> {
        if depth > MAX_DEPTH {
            return Err(self.error_at(offset, "dictionaries nested too deeply"));
        }
        let mut dict = Dict {
            entries: Vec::new(),
            offset,
        };
        loop {
            let at = self.skip_then_offset()?;
            let key = match self.token()? {
                Tok::Eof if depth == 0 => return Ok(dict),
                Tok::Punct(b'}') if depth > 0 => return Ok(dict),
                Tok::Word(w) if w.starts_with('#') || w.starts_with('$') => {
                    return Err(self.error_at(
                        at,
                        format!(
                            "directive or macro `{w}` is not supported: read a time directory written by the solver"
                        ),
                    ));
                }
                Tok::Word(w) | Tok::Str(w) => w.to_string(),
                other => return Err(self.error_at(at, format!("expected a keyword, found {}", describe(other)))),
            };
            let entry = if self.peek()? == Tok::Punct(b'{') {
                let brace = self.skip_then_offset()?;
                self.expect(b'{')?;
                Entry::Dict(self.dict_body(brace, depth + 1)?)
            } else {
                Entry::Values(self.values(depth)?)
            };
            dict.entries.push((key, entry, at));
        }
    }

    /// Values up to and including `;`.
    fn values(&mut self, depth: usize) -> Result<Vec<Value>, FoamError> {
        let mut out = Vec::new();
        loop {
            let at = self.skip_then_offset()?;
            match self.token()? {
                Tok::Punct(b';') => return Ok(out),
                Tok::Word(w) if w.starts_with("List<") => match components(w) {
                    Some(comps) => out.push(Value::Numbers(self.numbers(comps)?)),
                    // Lists of words and the like are ASCII even in binary files: the count is
                    // redundant with the parenthesised items that follow.
                    None => {
                        self.count()?;
                        let at = self.skip_then_offset()?;
                        let tok = self.token()?;
                        if tok != Tok::Punct(b'(') {
                            return Err(self.error_at(
                                at,
                                format!("expected `(` after `{w}` and its count, found {}", describe(tok)),
                            ));
                        }
                        out.push(self.value(tok, at, depth + 1)?);
                    }
                },
                tok => out.push(self.value(tok, at, depth + 1)?),
            }
        }
    }

    fn value(&mut self, tok: Tok<'a>, at: usize, depth: usize) -> Result<Value, FoamError> {
        if depth > MAX_DEPTH {
            return Err(self.error_at(at, "lists nested too deeply"));
        }
        match tok {
            Tok::Word(w) if w.starts_with('$') || w.starts_with('#') => Err(self.error_at(
                at,
                format!("directive or macro `{w}` is not supported: read a time directory written by the solver"),
            )),
            Tok::Word(w) => Ok(Value::Word(w.to_string())),
            Tok::Str(s) => Ok(Value::Str(s.to_string())),
            Tok::Punct(b'(') => {
                let mut items = Vec::new();
                loop {
                    let at = self.skip_then_offset()?;
                    match self.token()? {
                        Tok::Punct(b')') => return Ok(Value::List(items)),
                        tok => items.push(self.value(tok, at, depth + 1)?),
                    }
                }
            }
            Tok::Punct(b'[') => loop {
                let at = self.skip_then_offset()?;
                match self.token()? {
                    Tok::Punct(b']') => return Ok(Value::Dims),
                    Tok::Word(_) => {}
                    other => return Err(self.error_at(at, format!("in dimensions: unexpected {}", describe(other)))),
                }
            },
            other => Err(self.error_at(at, format!("unexpected {}", describe(other)))),
        }
    }

    /// `n ( ... )` or `n {v}` of elements with `comps` scalar components each.
    pub fn numbers(&mut self, comps: usize) -> Result<Numbers, FoamError> {
        let offset = self.skip_then_offset()?;
        let count = self.count()?;
        let open = self.skip_then_offset()?;
        match self.token()? {
            Tok::Punct(b'{') => {
                // The uniform form `n{v}`; in binary files v is raw bytes.
                let data = if self.binary {
                    self.scalars(1, comps, offset)?
                } else {
                    self.ascii_elements(1, comps, offset)?
                };
                self.expect(b'}')?;
                Ok(Numbers {
                    comps,
                    count,
                    data,
                    offset,
                })
            }
            Tok::Punct(b'(') => {
                let data = if self.binary {
                    self.scalars(count, comps, offset)?
                } else {
                    self.ascii_elements(count, comps, offset)?
                };
                self.expect(b')')?;
                Ok(Numbers {
                    comps,
                    count,
                    data,
                    offset,
                })
            }
            other => Err(self.error_at(
                open,
                format!("expected `(` or `{{` after the count, found {}", describe(other)),
            )),
        }
    }

    /// `n ( ... )` or `n {l}` of non-negative labels below `u32::MAX`, expanded.
    pub fn labels(&mut self) -> Result<Vec<u32>, FoamError> {
        self.label_list(0, i64::from(u32::MAX), |v| v as u32)
    }

    /// `n ( ... )` or `n {l}` of labels in `-(2³² − 1)..2³² − 1`, expanded: the decomposition's
    /// addressing, whose signs carry meaning (`faceProcAddressing`, `boundaryProcAddressing`).
    pub fn signed_labels(&mut self) -> Result<Vec<i64>, FoamError> {
        self.label_list(-i64::from(u32::MAX) + 1, i64::from(u32::MAX), |v| v)
    }

    /// A label list whose values lie in `lo..hi`, each stored as `cast` of it.
    fn label_list<T: Copy>(&mut self, lo: i64, hi: i64, cast: fn(i64) -> T) -> Result<Vec<T>, FoamError> {
        let offset = self.skip_then_offset()?;
        let count = self.count()?;
        let open = self.skip_then_offset()?;
        let out = match self.token()? {
            Tok::Punct(b'{') => {
                let l = if self.binary {
                    self.binary_labels(1, (lo, hi), |v| v, offset)?[0]
                } else {
                    self.ascii_label(lo, hi)?
                };
                self.expect(b'}')?;
                // The uniform form costs no bytes per element, so bound it by the file size:
                // no mesh list is longer than the number of bytes in its file.
                if count > self.text.len() {
                    return Err(self.error_at(
                        offset,
                        format!("uniform list of {count} labels is longer than the file"),
                    ));
                }
                vec![cast(l); count]
            }
            Tok::Punct(b'(') => {
                let out = if self.binary {
                    self.binary_labels(count, (lo, hi), cast, offset)?
                } else {
                    self.check_room(count, 2, offset)?;
                    let mut out = Vec::with_capacity(count);
                    for _ in 0..count {
                        out.push(cast(self.ascii_label(lo, hi)?));
                    }
                    out
                };
                self.expect(b')')?;
                out
            }
            other => {
                return Err(self.error_at(
                    open,
                    format!("expected `(` or `{{` after the count, found {}", describe(other)),
                ));
            }
        };
        Ok(out)
    }

    fn ascii_label(&mut self, lo: i64, hi: i64) -> Result<i64, FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Word(w) => w
                .parse::<i64>()
                .ok()
                .filter(|v| (lo..hi).contains(v))
                .ok_or_else(|| self.error_at(at, format!("expected a label (integer in {lo}..{hi}), found `{w}`"))),
            other => Err(self.error_at(at, format!("expected a label, found {}", describe(other)))),
        }
    }

    /// A scalar written in ASCII.
    pub fn ascii_scalar(&mut self) -> Result<f64, FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Word(w) => w
                .parse::<f64>()
                .map_err(|_| self.error_at(at, format!("expected a number, found `{w}`"))),
            other => Err(self.error_at(at, format!("expected a number, found {}", describe(other)))),
        }
    }

    /// Fail unless `count` elements of at least `min_bytes` each fit in the rest of the file.
    pub fn check_room(&self, count: usize, min_bytes: usize, offset: usize) -> Result<(), FoamError> {
        let left = self.text.len() - self.pos;
        match count.checked_mul(min_bytes) {
            Some(need) if need <= left => Ok(()),
            _ => Err(self.error_at(
                offset,
                format!("list declares {count} elements but only {left} bytes remain"),
            )),
        }
    }

    fn ascii_elements(&mut self, count: usize, comps: usize, offset: usize) -> Result<Vec<f64>, FoamError> {
        // Shortest element: "0 " per component, plus "()" around a tuple.
        let min = 2 * comps + if comps > 1 { 2 } else { 0 };
        self.check_room(count, min, offset)?;
        let mut data = Vec::with_capacity(count * comps);
        for _ in 0..count {
            if comps > 1 {
                self.expect(b'(')?;
            }
            for _ in 0..comps {
                data.push(self.ascii_scalar()?);
            }
            if comps > 1 {
                self.expect(b')')?;
            }
        }
        Ok(data)
    }

    fn scalars(&mut self, count: usize, comps: usize, offset: usize) -> Result<Vec<f64>, FoamError> {
        let size = self.scalar_bytes;
        Ok(self
            .binary_block(count, comps, size, offset)?
            .chunks_exact(size)
            .map(|c| match c.len() {
                8 => f64::from_le_bytes(c.try_into().expect("8-byte chunk")),
                _ => f64::from(f32::from_le_bytes(c.try_into().expect("4-byte chunk"))),
            })
            .collect())
    }

    fn binary_labels<T>(
        &mut self,
        count: usize,
        (lo, hi): (i64, i64),
        cast: fn(i64) -> T,
        offset: usize,
    ) -> Result<Vec<T>, FoamError> {
        let lb = self.label_bytes;
        let block = self.binary_block(count, 1, lb, offset)?;
        let mut out = Vec::with_capacity(count);
        for (i, c) in block.chunks_exact(lb).enumerate() {
            let v = match c.len() {
                4 => i64::from(i32::from_le_bytes(c.try_into().expect("4-byte chunk"))),
                _ => i64::from_le_bytes(c.try_into().expect("8-byte chunk")),
            };
            if !(lo..hi).contains(&v) {
                return Err(self.error_at(offset, format!("label {i} of the list is {v}, outside {lo}..{hi}")));
            }
            out.push(cast(v));
        }
        Ok(out)
    }

    fn binary_block(&mut self, count: usize, comps: usize, size: usize, offset: usize) -> Result<&'a [u8], FoamError> {
        let len = count
            .checked_mul(comps)
            .and_then(|n| n.checked_mul(size))
            .filter(|&n| n <= self.text.len() - self.pos)
            .ok_or_else(|| {
                self.error_at(
                    offset,
                    format!(
                        "binary list declares {count} elements of {} bytes but only {} bytes remain",
                        comps * size,
                        self.text.len() - self.pos
                    ),
                )
            })?;
        let block = &self.text[self.pos..self.pos + len];
        self.pos += len;
        Ok(block)
    }

    /// Fail unless only whitespace and comments remain.
    pub fn end(&mut self) -> Result<(), FoamError> {
        let at = self.skip_then_offset()?;
        match self.token()? {
            Tok::Eof => Ok(()),
            other => Err(self.error_at(at, format!("unexpected {} after the data", describe(other)))),
        }
    }
}

/// Scalar components of a `List<T>` element type.
fn components(list_type: &str) -> Option<usize> {
    match list_type.strip_prefix("List<")?.strip_suffix('>')? {
        "scalar" => Some(1),
        "vector" => Some(3),
        "symmTensor" => Some(6),
        "tensor" => Some(9),
        "sphericalTensor" => Some(1),
        _ => None,
    }
}

fn describe(tok: Tok<'_>) -> String {
    match tok {
        Tok::Punct(p) => format!("`{}`", p as char),
        Tok::Word(w) => format!("`{}`", w.chars().take(40).collect::<String>()),
        Tok::Str(s) => format!("string \"{}\"", s.chars().take(40).collect::<String>()),
        Tok::Eof => "end of file".to_string(),
    }
}

/// Parse a whole file: header, then the body as a dictionary.
pub(crate) fn dictionary_file(path: &str, text: &[u8]) -> Result<(Header, Dict), FoamError> {
    let mut p = Parser::new(path, text);
    let header = p.header()?;
    let dict = p.dict_body(0, 0)?;
    Ok((header, dict))
}

/// A value as a number (e.g. an element of `uniform (1 0 0)`).
pub(crate) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Word(w) => w.parse().ok(),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(format: &str, arch: &str) -> Vec<u8> {
        format!("FoamFile {{ format {format}; class labelList; arch \"{arch}\"; }}\n").into_bytes()
    }

    #[test]
    fn uniform_lists_ascii_and_binary() {
        let mut text = header("ascii", "LSB;label=32;scalar=64");
        text.extend(b"4{7}\n");
        let mut p = Parser::new("t", &text);
        p.header().unwrap();
        assert_eq!(p.labels().unwrap(), vec![7; 4]);
        p.end().unwrap();

        let mut text = header("binary", "LSB;label=64;scalar=32");
        text.extend(b"3{");
        text.extend(9i64.to_le_bytes());
        text.extend(b"}\n2(");
        for x in [1.5f32, -2.25, 0.0, 1.0, 2.0, 3.0] {
            text.extend(x.to_le_bytes());
        }
        text.extend(b")\n");
        let mut p = Parser::new("t", &text);
        p.header().unwrap();
        assert_eq!(p.labels().unwrap(), vec![9; 3]);
        let v = p.numbers(3).unwrap();
        assert_eq!((v.count, v.data), (2, vec![1.5, -2.25, 0.0, 1.0, 2.0, 3.0]));
        p.end().unwrap();
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let mut text = header("ascii", "");
        text.extend(b"a ");
        text.extend(std::iter::repeat_n(b'(', 10_000));
        text.extend(b";\n");
        let err = dictionary_file("t", &text).unwrap_err();
        assert!(err.to_string().contains("nested too deeply"), "{err}");
    }

    #[test]
    fn errors_report_line_and_offset() {
        let text = b"// comment\nFoamFile { format ascii; class labelList; }\n2\n(\n1\nx\n)\n";
        let mut p = Parser::new("t", text);
        p.header().unwrap();
        match p.labels().unwrap_err() {
            FoamError::Malformed { line, offset, .. } => {
                assert_eq!(line, 6);
                assert_eq!(&text[offset..offset + 1], b"x");
            }
            other => panic!("{other:?}"),
        }
    }
}

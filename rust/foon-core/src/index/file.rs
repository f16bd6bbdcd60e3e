//! `.foonidx`: the index as a file, opened with a memory map and no copies.
//!
//! # Layout (format version 1)
//!
//! All integers are little-endian. A file is a 128-byte header, a column table of 24-byte
//! entries, then the columns, each starting at an offset that is a multiple of 8 (the gaps
//! are zero bytes). Nothing in it is executable or self-describing beyond plain integers.
//!
//! | bytes   | field | meaning |
//! |---------|-------|---------|
//! | 0–7     | magic | `89 46 4F 4F 4E 49 44 58` (`\x89FOONIDX`) |
//! | 8–11    | version | `1`; a larger version is refused ("newer than this foon reads") |
//! | 12–15   | endianness mark | `0x0A0B0C0D` (bytes `0D 0C 0B 0A`) |
//! | 16–19   | flags | `0` (no flags are defined in version 1) |
//! | 20–23   | column count | 41 in version 1 |
//! | 24–31   | file length | bytes, header included |
//! | 32–47   | fingerprint | XXH3-128 of the content columns (see [`Foon::fingerprint`]) |
//! | 48–55   | data checksum | XXH3-64 (seed 0) of the bytes from the data start to the end |
//! | 56–63   | data start | `128 + 24 × column count`, rounded up to a multiple of 8 |
//! | 64–103  | counts | strings, objects, variants, functional units, sources (5 × u64) |
//! | 104–111 | header checksum | XXH3-64 (seed 0) of bytes 0 to the data start, this field read as zero |
//! | 112–127 | reserved | zero |
//!
//! Each column table entry: column id (u32), element size in bytes (u32: 1, 4 or 8), byte
//! offset (u64), length in elements (u64). The columns of version 1, by id (see
//! [`COLUMNS`]): strings (text, end offsets, hashes, look-up table), objects (label,
//! container, states and ingredients as CSR offset + data, first variant, hash, table),
//! variants (object, states, ingredients), FUs (motion, motion metadata, line, inputs and
//! outputs as CSR, the written variant and object-in-motion flag of each input and output),
//! producers and consumers (CSR), distinct motions, FU hashes and table, source names (text,
//! end offsets), the source of each FU and its further (source, line) origins (CSR).
//! "No value" is `u32::MAX`; an empty table slot is `u32::MAX` (see [`super::hash`] for the
//! hash functions and the table layout).
//!
//! # Opening
//!
//! [`Foon::open_index`] maps the file read-only and checks, in time linear in the number of
//! columns, the header, the header checksum and that every column lies inside the file with
//! the element size of its id. It then checks the invariants that the search code relies on,
//! so that no later access can panic: CSR offsets start at 0, never decrease and end at the
//! data length; every id is in range (or "no value" where allowed); tables have a
//! power-of-two size, an empty slot and entries in range; string ends increase, fall on UTF-8
//! boundaries and the text is UTF-8; producers and consumers are exactly the relation the FU
//! rows give (each row in order, and equal multisets of (object, FU) pairs from both sides,
//! compared by keyed 64-bit sums with a key random per process). These checks are one pass
//! over the columns, split in chunks of 2^18 elements shared by the cores; each scan is a
//! branch-free maximum or comparison (the position is looked for only in a failing chunk) and
//! cannot panic on any bytes, so all run at once, and the first failure in a fixed order is
//! reported. The per-column hashes and the unit lines are not read at all. The data checksum
//! is verified on request ([`Foon::verify_checksum`]; `foon check` does). Any failure is an
//! [`Error::BadIndex`] naming the file and what is wrong; `foon check` reports it as
//! `FILE: error: REASON [bad-index]` (a finding about the whole file has line and column 0
//! in `--json` and in `foon.check`, and no `:LINE:COLUMN` when printed). The file carries the
//! index only (columns, strings, sources and provenance),
//! not the load report: a FOON opened from a file has an empty report.
//!
//! A mapped file must not be changed while it is open (replace it by renaming a new file over
//! it, as [`Foon::write_index_file`] does); changing it in place is not supported. Big-endian
//! hosts are refused with a clear error (the columns are little-endian and used in place).

use std::borrow::Cow;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use xxhash_rust::xxh3::{Xxh3, xxh3_64};

use super::col::{Backing, Col};
use super::hash::{EMPTY, SEED};
use super::{Foon, NONE};
use crate::error::{Error, Result};

/// The first bytes of every index file.
pub const MAGIC: [u8; 8] = *b"\x89FOONIDX";
/// The format version this code writes and reads.
pub const VERSION: u32 = 1;
const ENDIAN_MARK: u32 = 0x0A0B_0C0D;
const HEADER: usize = 128;
const ENTRY: usize = 24;

/// Where an opened FOON's bytes come from.
#[derive(Debug)]
pub(crate) struct Opened {
    pub(crate) path: Option<PathBuf>,
    backing: Arc<Backing>,
    checksum: u64,
    data_start: usize,
}

/// A column of the index, by element type.
pub(crate) enum ColRef<'a> {
    U8(&'a Col<u8>),
    U32(&'a Col<u32>),
    U64(&'a Col<u64>),
}

impl ColRef<'_> {
    pub(crate) fn heap_bytes(&self) -> usize {
        match self {
            Self::U8(c) => c.heap_bytes(),
            Self::U32(c) => c.heap_bytes(),
            Self::U64(c) => c.heap_bytes(),
        }
    }

    fn elem(&self) -> usize {
        match self {
            Self::U8(_) => 1,
            Self::U32(_) => 4,
            Self::U64(_) => 8,
        }
    }

    fn len(&self) -> usize {
        match self {
            Self::U8(c) => c.len(),
            Self::U32(c) => c.len(),
            Self::U64(c) => c.len(),
        }
    }

    /// The little-endian bytes of the column (borrowed on little-endian hosts).
    fn le_bytes(&self) -> Cow<'_, [u8]> {
        if cfg!(target_endian = "little") {
            Cow::Borrowed(match self {
                Self::U8(c) => c,
                Self::U32(c) => bytemuck::cast_slice(c),
                Self::U64(c) => bytemuck::cast_slice(c),
            })
        } else {
            Cow::Owned(match self {
                Self::U8(c) => c.to_vec(),
                Self::U32(c) => c.iter().flat_map(|x| x.to_le_bytes()).collect(),
                Self::U64(c) => c.iter().flat_map(|x| x.to_le_bytes()).collect(),
            })
        }
    }
}

enum ColMut<'a> {
    U8(&'a mut Col<u8>),
    U32(&'a mut Col<u32>),
    U64(&'a mut Col<u64>),
}

impl ColMut<'_> {
    fn elem(&self) -> usize {
        match self {
            Self::U8(_) => 1,
            Self::U32(_) => 4,
            Self::U64(_) => 8,
        }
    }

    fn set(&mut self, map: &Arc<Backing>, off: usize, len: usize) {
        match self {
            Self::U8(c) => **c = Col::mapped(map, off, len),
            Self::U32(c) => **c = Col::mapped(map, off, len),
            Self::U64(c) => **c = Col::mapped(map, off, len),
        }
    }
}

macro_rules! column_list {
    ($( $name:literal $content:literal $kind:ident $($field:ident).+ ; )*) => {
        /// The columns of format version 1: `(name, content)`, the id of a column being its
        /// position here plus one. Content columns enter the fingerprint; the others (hashes
        /// and tables) follow from them.
        pub const COLUMNS: &[(&str, bool)] = &[$(($name, $content)),*];

        impl Foon {
            pub(crate) fn columns(&self) -> Vec<ColRef<'_>> {
                vec![$(ColRef::$kind(&self.$($field).+)),*]
            }

            fn columns_mut(&mut self) -> Vec<ColMut<'_>> {
                vec![$(ColMut::$kind(&mut self.$($field).+)),*]
            }
        }
    };
}

column_list! {
    "str_text" true U8 strings.list.text;
    "str_ends" true U64 strings.list.ends;
    "str_hash" false U32 strings.hashes;
    "str_table" false U32 strings.table.slots;
    "obj_label" true U32 obj_label;
    "obj_container" true U32 obj_container;
    "obj_states_off" true U32 obj_states.off;
    "obj_states" true U32 obj_states.data;
    "obj_ingredients_off" true U32 obj_ingredients.off;
    "obj_ingredients" true U32 obj_ingredients.data;
    "obj_first_variant" true U32 obj_first_variant;
    "obj_hash" false U32 obj_hash;
    "obj_table" false U32 obj_table.slots;
    "var_obj" true U32 var_obj;
    "var_states_off" true U32 var_states.off;
    "var_states" true U32 var_states.data;
    "var_ingredients_off" true U32 var_ingredients.off;
    "var_ingredients" true U32 var_ingredients.data;
    "fu_motion" true U32 fu_motion;
    "fu_motion_meta" true U32 fu_motion_meta;
    "fu_line" true U32 fu_line;
    "fu_inputs_off" true U32 fu_inputs.off;
    "fu_inputs" true U32 fu_inputs.data;
    "fu_outputs_off" true U32 fu_outputs.off;
    "fu_outputs" true U32 fu_outputs.data;
    "fu_input_variant" true U32 fu_input_variant;
    "fu_output_variant" true U32 fu_output_variant;
    "fu_input_in_motion" true U8 fu_input_in_motion;
    "fu_output_in_motion" true U8 fu_output_in_motion;
    "producers_off" true U32 producers.off;
    "producers" true U32 producers.data;
    "consumers_off" true U32 consumers.off;
    "consumers" true U32 consumers.data;
    "motions" true U32 motions;
    "fu_hash" false U32 fu_hash;
    "fu_table" false U32 fu_table.slots;
    "src_text" true U8 sources.text;
    "src_ends" true U64 sources.ends;
    "fu_source" true U32 fu_source;
    "fu_also_off" true U32 fu_also.off;
    "fu_also" true U32 fu_also.data;
}

/// The fingerprint of `foon`'s content columns (see [`Foon::fingerprint`]): XXH3-128 with the
/// identity-hash seed over, for each content column in id order, its id (u32), element size
/// (u32), length (u64) and little-endian bytes.
pub(crate) fn fingerprint_of(foon: &Foon) -> [u8; 16] {
    let mut h = Xxh3::with_seed(SEED);
    for (i, c) in foon.columns().iter().enumerate() {
        if !COLUMNS[i].1 {
            continue;
        }
        h.update(&(i as u32 + 1).to_le_bytes());
        h.update(&(c.elem() as u32).to_le_bytes());
        h.update(&(c.len() as u64).to_le_bytes());
        h.update(&c.le_bytes());
    }
    h.digest128().to_le_bytes()
}

fn pad8(n: usize) -> usize {
    n.div_ceil(8) * 8
}

fn put_u32(b: &mut [u8], at: usize, v: u32) {
    b[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

fn put_u64(b: &mut [u8], at: usize, v: u64) {
    b[at..at + 8].copy_from_slice(&v.to_le_bytes());
}

fn get_u32(b: &[u8], at: usize) -> u32 {
    b.get(at..at + 4)
        .and_then(|s| s.try_into().ok())
        .map_or(0, u32::from_le_bytes)
}

fn get_u64(b: &[u8], at: usize) -> u64 {
    b.get(at..at + 8)
        .and_then(|s| s.try_into().ok())
        .map_or(0, u64::from_le_bytes)
}

impl Foon {
    fn counts(&self) -> [u64; 5] {
        [
            self.strings.len() as u64,
            self.object_count() as u64,
            self.var_obj.len() as u64,
            self.fu_count() as u64,
            self.sources.len() as u64,
        ]
    }

    /// Writes the index as a `.foonidx` file (see the module documentation) to `out`. The
    /// same index always gives the same bytes.
    pub fn write_index(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let cols = self.columns();
        let data_start = pad8(HEADER + ENTRY * cols.len());
        let mut header = vec![0u8; data_start];
        let mut pos = data_start;
        let mut sum = Xxh3::new();
        let zeros = [0u8; 8];
        for (i, c) in cols.iter().enumerate() {
            let e = HEADER + ENTRY * i;
            put_u32(&mut header, e, i as u32 + 1);
            put_u32(&mut header, e + 4, c.elem() as u32);
            put_u64(&mut header, e + 8, pos as u64);
            put_u64(&mut header, e + 16, c.len() as u64);
            let bytes = c.le_bytes();
            sum.update(&bytes);
            let padded = pad8(bytes.len());
            sum.update(&zeros[..padded - bytes.len()]);
            pos += padded;
        }
        header[..8].copy_from_slice(&MAGIC);
        put_u32(&mut header, 8, VERSION);
        put_u32(&mut header, 12, ENDIAN_MARK);
        put_u32(&mut header, 16, 0);
        put_u32(&mut header, 20, cols.len() as u32);
        put_u64(&mut header, 24, pos as u64);
        header[32..48].copy_from_slice(&self.fingerprint());
        put_u64(&mut header, 48, sum.digest());
        put_u64(&mut header, 56, data_start as u64);
        for (k, n) in self.counts().into_iter().enumerate() {
            put_u64(&mut header, 64 + 8 * k, n);
        }
        let hsum = xxh3_64(&header);
        put_u64(&mut header, 104, hsum);
        out.write_all(&header)?;
        for c in &cols {
            let bytes = c.le_bytes();
            out.write_all(&bytes)?;
            out.write_all(&zeros[..pad8(bytes.len()) - bytes.len()])?;
        }
        out.flush()
    }

    /// The index as `.foonidx` bytes (see [`Foon::write_index`]).
    pub fn index_bytes(&self) -> Vec<u8> {
        let mut v = Vec::new();
        // Writing into a vector cannot fail.
        let _ = self.write_index(&mut v);
        v
    }

    /// Writes the index to `path` atomically (see [`crate::atomic`]). Refuses a path that is
    /// one of the FOON's sources or the index file it was opened from.
    pub fn write_index_file(&self, path: &Path) -> Result<()> {
        let inputs: Vec<&Path> = (0..self.source_count() as u32)
            .map(|s| self.source_name(s))
            .filter(|s| !s.is_empty())
            .map(Path::new)
            .chain(self.index_path())
            .collect();
        crate::atomic::write_atomic(path, &inputs, |w| {
            self.write_index(w).map_err(|e| Error::io(path, e))
        })
    }

    /// Opens an index file (see the module documentation) with a read-only memory map: the
    /// columns are used in place, nothing is copied.
    pub fn open_index(path: &Path) -> Result<Foon> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let meta = file.metadata().map_err(|e| Error::io(path, e))?;
        if !meta.is_file() {
            return Err(bad(path, "not a regular file"));
        }
        let map = map_file(&file).map_err(|e| Error::io(path, e))?;
        open_backing(&Arc::new(Backing::Map(map)), Some(path), path)
    }

    /// Opens index bytes held in memory (as [`Foon::index_bytes`] gives them); they are
    /// copied once into aligned memory. `name` names the source in errors.
    pub fn from_index_bytes(data: &[u8], name: &Path) -> Result<Foon> {
        open_backing(&Arc::new(Backing::copy_of(data)), None, name)
    }

    /// Verifies the data checksum (and the fingerprint) of a FOON opened from an index file;
    /// `Ok` for a FOON built in memory, which has nothing to verify.
    pub fn verify_checksum(&self) -> Result<()> {
        let Some(f) = &self.file else { return Ok(()) };
        let name = f.path.clone().unwrap_or_else(|| "<bytes>".into());
        let data = f.backing.bytes().get(f.data_start..).unwrap_or(&[]);
        let sum = data_xxh3(data);
        if sum != f.checksum {
            return Err(bad(
                &name,
                &format!(
                    "checksum mismatch: the data hashes to {sum:016x}, the header says {:016x}",
                    f.checksum
                ),
            ));
        }
        if fingerprint_of(self) != self.fingerprint() {
            return Err(bad(
                &name,
                "fingerprint mismatch: the columns do not match the header's fingerprint",
            ));
        }
        Ok(())
    }
}

/// XXH3-64 of `data` (one pass; kept as one function so the checksum is defined once).
fn data_xxh3(data: &[u8]) -> u64 {
    xxh3_64(data)
}

/// Maps `file` read-only.
#[allow(unsafe_code)]
fn map_file(file: &std::fs::File) -> std::io::Result<memmap2::Mmap> {
    // SAFETY: the file is opened read-only and the map is never written through. Another
    // process changing the file while it is mapped is not supported (documented above): the
    // opened index would see the new bytes. Every access to the map goes through bounds- and
    // alignment-checked slices, and the structure is validated before use.
    unsafe { memmap2::Mmap::map(file) }
}

fn bad(path: &Path, reason: &str) -> Error {
    Error::BadIndex {
        path: path.to_path_buf(),
        reason: reason.to_owned(),
    }
}

/// Whether `data` starts with the index magic.
pub fn is_index(data: &[u8]) -> bool {
    data.starts_with(&MAGIC)
}

/// Whether `path` is named as an index file (`.foonidx`, in any case): such a file is opened
/// as one, and is an error when it is not (a truncated or empty file included), rather than
/// read as FOON text.
pub fn is_index_name(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("foonidx"))
}

/// Whether the file at `path` is to be opened as an index (the rule of every command): it
/// is named as one ([`is_index_name`]) or starts with the index magic (false when it cannot
/// be read).
pub fn is_index_file(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 8];
    is_index_name(path)
        || (std::fs::File::open(path)
            .and_then(|mut f| f.read_exact(&mut head))
            .is_ok()
            && head == MAGIC)
}

fn open_backing(backing: &Arc<Backing>, path: Option<&Path>, name: &Path) -> Result<Foon> {
    let err = |r: String| bad(name, &r);
    if cfg!(target_endian = "big") {
        return Err(err(
            "index files are little-endian and are used in place: big-endian hosts are not supported"
                .into(),
        ));
    }
    let b = backing.bytes();
    let len = b.len();
    if len < HEADER {
        return Err(err(format!(
            "truncated: the header needs {HEADER} bytes, the file has {len}"
        )));
    }
    if b[..8] != MAGIC {
        return Err(err("not a FOON index file (bad magic)".into()));
    }
    let version = get_u32(b, 8);
    if version != VERSION {
        return Err(err(if version > VERSION {
            format!("format version {version} is newer than this foon reads ({VERSION})")
        } else {
            format!("unknown format version {version}")
        }));
    }
    if get_u32(b, 12) != ENDIAN_MARK {
        return Err(err(format!(
            "bad endianness mark {:#010x} (expected {ENDIAN_MARK:#010x}, little-endian)",
            get_u32(b, 12)
        )));
    }
    let flags = get_u32(b, 16);
    if flags != 0 {
        return Err(err(format!("unknown flags {flags:#x}")));
    }
    let declared = get_u64(b, 24);
    if declared != len as u64 {
        return Err(err(if declared > len as u64 {
            format!("truncated: the header says {declared} bytes, the file has {len}")
        } else {
            format!(
                "{} bytes after the end given in the header ({declared})",
                len as u64 - declared
            )
        }));
    }
    let n_cols = get_u32(b, 20) as usize;
    if n_cols != COLUMNS.len() {
        return Err(err(format!(
            "{n_cols} columns; format version {VERSION} has {}",
            COLUMNS.len()
        )));
    }
    let data_start = pad8(HEADER + ENTRY * n_cols);
    if get_u64(b, 56) != data_start as u64 || data_start > len {
        return Err(err(format!(
            "bad data start {} (expected {data_start}, file of {len} bytes)",
            get_u64(b, 56)
        )));
    }
    let mut head = b[..data_start].to_vec();
    put_u64(&mut head, 104, 0);
    if xxh3_64(&head) != get_u64(b, 104) {
        return Err(err(
            "header checksum mismatch: the header or column table is corrupt".into(),
        ));
    }
    let mut foon = Foon::default();
    let mut seen = vec![false; n_cols];
    {
        let mut cols = foon.columns_mut();
        for i in 0..n_cols {
            let e = HEADER + ENTRY * i;
            let id = get_u32(b, e) as usize;
            let elem = get_u32(b, e + 4) as usize;
            let off = get_u64(b, e + 8);
            let n = get_u64(b, e + 16);
            let Some(slot) = id.checked_sub(1).filter(|&k| k < n_cols) else {
                return Err(err(format!("column entry {i} has an unknown id {id}")));
            };
            let cname = COLUMNS[slot].0;
            if std::mem::replace(&mut seen[slot], true) {
                return Err(err(format!("column {cname} is given twice")));
            }
            let col = &mut cols[slot];
            if elem != col.elem() {
                return Err(err(format!(
                    "column {cname} has elements of {elem} bytes, not {}",
                    col.elem()
                )));
            }
            if off % 8 != 0 || off < data_start as u64 {
                return Err(err(format!("column {cname} starts at a bad offset {off}")));
            }
            let end = n
                .checked_mul(elem as u64)
                .and_then(|x| x.checked_add(off))
                .unwrap_or(u64::MAX);
            if end > len as u64 {
                return Err(err(format!(
                    "truncated: column {cname} ends at byte {end} of {len}"
                )));
            }
            col.set(backing, off as usize, n as usize);
        }
    }
    let counts = foon.counts();
    for (k, what) in [
        "strings",
        "objects",
        "variants",
        "functional units",
        "sources",
    ]
    .iter()
    .enumerate()
    {
        let said = get_u64(b, 64 + 8 * k);
        if said != counts[k] {
            return Err(err(format!(
                "the header counts {said} {what}, the columns hold {}",
                counts[k]
            )));
        }
    }
    validate(&foon).map_err(err)?;
    let mut fp = [0u8; 16];
    fp.copy_from_slice(&b[32..48]);
    let _ = foon.fingerprint.set(fp);
    foon.file = Some(Arc::new(Opened {
        path: path.map(Path::to_path_buf),
        checksum: get_u64(b, 48),
        data_start,
        backing: Arc::clone(backing),
    }));
    Ok(foon)
}

type Res = std::result::Result<(), String>;

/// Elements a part of a column check covers (1 MiB of `u32`): large columns are split so
/// that the cores share them evenly.
const CHUNK: usize = 1 << 18;

/// One check of the structure, run as `parts` independent parts (part `k` covers the chunk
/// [`chunk_range`] gives for `k`).
struct Job<'a> {
    parts: u32,
    work: Box<dyn Fn(u32) -> Res + Sync + 'a>,
}

impl<'a> Job<'a> {
    fn one(work: impl Fn() -> Res + Sync + 'a) -> Self {
        Self {
            parts: 1,
            work: Box::new(move |_| work()),
        }
    }

    /// A check of `len` elements in chunks: `work(range)` for each chunk.
    fn chunked(len: usize, work: impl Fn(Range<usize>) -> Res + Sync + 'a) -> Self {
        Self {
            parts: len.div_ceil(CHUNK).max(1) as u32,
            work: Box::new(move |k| work(chunk_range(len, k))),
        }
    }
}

fn chunk_range(len: usize, k: u32) -> Range<usize> {
    let lo = (k as usize).saturating_mul(CHUNK).min(len);
    lo..lo.saturating_add(CHUNK).min(len)
}

/// The lengths every column must have, then the invariants the search code relies on
/// (module documentation): every column scan and the adjacency check, split in chunks and
/// run in one parallel pass. Each scan is written so that it cannot panic on any bytes
/// (the adjacency reads rows through ids that other parts of the pass check), and the first
/// failure in a fixed order (the order of the jobs, then of their parts) is reported.
fn validate(f: &Foon) -> Res {
    let n_str = f.strings.len();
    let n_obj = f.object_count();
    let n_var = f.var_obj.len();
    let n_fu = f.fu_count();
    let n_src = f.sources.len();
    let names: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    let cols = f.columns();
    let want_len = |name: &str, want: usize| -> Res {
        let k = names.iter().position(|&n| n == name).unwrap_or(0);
        let have = cols[k].len();
        if have == want {
            Ok(())
        } else {
            Err(format!("column {name} has {have} entries, expected {want}"))
        }
    };
    for (name, want) in [
        ("str_hash", n_str),
        ("obj_container", n_obj),
        ("obj_first_variant", n_obj),
        ("obj_hash", n_obj),
        ("fu_motion_meta", n_fu),
        ("fu_line", n_fu),
        ("fu_source", n_fu),
        ("fu_hash", n_fu),
        ("fu_input_variant", f.fu_inputs.data.len()),
        ("fu_input_in_motion", f.fu_inputs.data.len()),
        ("fu_output_variant", f.fu_outputs.data.len()),
        ("fu_output_in_motion", f.fu_outputs.data.len()),
    ] {
        want_len(name, want)?;
    }
    for (name, rows) in [
        ("obj_states_off", n_obj),
        ("obj_ingredients_off", n_obj),
        ("var_states_off", n_var),
        ("var_ingredients_off", n_var),
        ("fu_inputs_off", n_fu),
        ("fu_outputs_off", n_fu),
        ("producers_off", n_obj),
        ("consumers_off", n_obj),
        ("fu_also_off", n_fu),
    ] {
        let k = names.iter().position(|&n| n == name).unwrap_or(0);
        let have = cols[k].len();
        if have != rows + 1 && !(have == 0 && rows == 0) {
            return Err(format!(
                "column {name} has {have} entries, expected {}",
                rows + 1
            ));
        }
    }
    if f.fu_also.data.len() % 2 != 0 {
        return Err("column fu_also has an odd length (it holds (source, line) pairs)".into());
    }
    for (name, slots, n) in [
        ("str_table", &f.strings.table.slots, n_str),
        ("obj_table", &f.obj_table.slots, n_obj),
        ("fu_table", &f.fu_table.slots, n_fu),
    ] {
        table_size(name, slots, n)?;
    }
    let empties = [
        AtomicBool::new(f.strings.table.slots.is_empty()),
        AtomicBool::new(f.obj_table.slots.is_empty()),
        AtomicBool::new(f.fu_table.slots.is_empty()),
    ];
    let adj = Adjacency::new(f);
    let sums = std::sync::Mutex::new([PairSum::default(); 4]);
    let mut jobs: Vec<Job<'_>> = vec![
        Job::one(|| strings("str", &f.strings.list.text, &f.strings.list.ends)),
        Job::one(|| strings("src", &f.sources.text, &f.sources.ends)),
    ];
    for (name, c) in [
        ("obj_states", &f.obj_states),
        ("obj_ingredients", &f.obj_ingredients),
        ("var_states", &f.var_states),
        ("var_ingredients", &f.var_ingredients),
        ("fu_inputs", &f.fu_inputs),
        ("fu_outputs", &f.fu_outputs),
        ("producers", &f.producers),
        ("consumers", &f.consumers),
        ("fu_also", &f.fu_also),
    ] {
        let (off, data_len) = (&c.off[..], c.data.len());
        jobs.push(Job::chunked(off.len(), move |r| {
            csr(name, off, data_len, r)
        }));
    }
    for (name, col, bound, none) in [
        ("obj_label", &f.obj_label, n_str, false),
        ("obj_container", &f.obj_container, n_str, true),
        ("obj_states", &f.obj_states.data, n_str, false),
        ("obj_ingredients", &f.obj_ingredients.data, n_str, false),
        ("obj_first_variant", &f.obj_first_variant, n_var, false),
        ("var_obj", &f.var_obj, n_obj, false),
        ("var_states", &f.var_states.data, n_str, false),
        ("var_ingredients", &f.var_ingredients.data, n_str, false),
        ("fu_motion", &f.fu_motion, n_str, false),
        ("fu_motion_meta", &f.fu_motion_meta, n_str, true),
        ("fu_inputs", &f.fu_inputs.data, n_obj, false),
        ("fu_outputs", &f.fu_outputs.data, n_obj, false),
        ("fu_input_variant", &f.fu_input_variant, n_var, false),
        ("fu_output_variant", &f.fu_output_variant, n_var, false),
        ("producers", &f.producers.data, n_fu, false),
        ("consumers", &f.consumers.data, n_fu, false),
        ("motions", &f.motions, n_str, false),
        ("fu_source", &f.fu_source, n_src, false),
    ] {
        let col = &col[..];
        jobs.push(Job::chunked(col.len(), move |r| {
            ids(name, col, bound, none, r)
        }));
    }
    for (name, col) in [
        ("fu_input_in_motion", &f.fu_input_in_motion),
        ("fu_output_in_motion", &f.fu_output_in_motion),
    ] {
        let col = &col[..];
        jobs.push(Job::chunked(col.len(), move |r| flags(name, col, r)));
    }
    let also_col = &f.fu_also.data[..];
    jobs.push(Job::chunked(also_col.len(), move |r| {
        also(also_col, n_src, r)
    }));
    for ((name, slots, n), empty) in [
        ("str_table", &f.strings.table.slots, n_str),
        ("obj_table", &f.obj_table.slots, n_obj),
        ("fu_table", &f.fu_table.slots, n_fu),
    ]
    .into_iter()
    .zip(&empties)
    {
        let slots = &slots[..];
        jobs.push(Job::chunked(slots.len(), move |r| {
            table(name, slots, n, r, empty)
        }));
    }
    let (adj, sums) = (&adj, &sums);
    let add = move |part: [PairSum; 4]| {
        if let Ok(mut t) = sums.lock() {
            for (t, x) in t.iter_mut().zip(part) {
                *t = t.merge(x);
            }
        }
    };
    jobs.push(Job::chunked(n_obj, move |r| adj.objects(r).map(add)));
    jobs.push(Job::chunked(n_fu, move |r| {
        add(adj.fus(r));
        Ok(())
    }));
    run_all(&jobs)?;
    for (name, empty) in ["str_table", "obj_table", "fu_table"]
        .into_iter()
        .zip(&empties)
    {
        if !empty.load(Ordering::Relaxed) {
            return Err(format!("column {name} has no empty slot"));
        }
    }
    let total = sums.lock().map(|t| *t).unwrap_or_default();
    if total[0] != total[2] {
        return Err("column producers does not match the FU outputs".into());
    }
    if total[1] != total[3] {
        return Err("column consumers does not match the FU inputs".into());
    }
    Ok(())
}

/// Runs every part of every job on scoped threads (one per core, each taking the next
/// part), and reports the first failure in (job, part) order. Scoped threads end with the
/// call: nothing is left running (a process forked afterwards, as `multiprocessing` does,
/// is unaffected).
fn run_all(jobs: &[Job<'_>]) -> Res {
    let mut at = Vec::new();
    for (j, job) in jobs.iter().enumerate() {
        at.extend((0..job.parts).map(|k| (j, k)));
    }
    par_parts(at.len() as u32, |i| {
        let (j, k) = at[i as usize];
        (jobs[j].work)(k)
    })
    .into_iter()
    .collect()
}

/// A keyed sum of a mix of `(object, FU)` pairs: equal multisets of pairs give equal sums;
/// unequal ones, unequal sums but with a negligible probability (the key is random per
/// process, so a file cannot be made to collide on purpose).
#[derive(Clone, Copy, Default, PartialEq, Eq)]
struct PairSum(u64);

impl PairSum {
    #[inline]
    fn add(&mut self, key: u64, o: u32, f: u32) {
        let x = (u64::from(o) << 32) | u64::from(f);
        self.0 = self.0.wrapping_add(mix(x ^ key));
    }

    fn merge(self, o: Self) -> Self {
        Self(self.0.wrapping_add(o.0))
    }
}

#[inline]
fn mix(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

/// A per-process random key for [`PairSum`].
fn pair_key() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(1);
    h.finish()
}

/// Row `i` of a CSR given as slices; empty when the offsets are out of range or decrease.
#[inline]
fn row<'a>(off: &[u32], data: &'a [u32], i: usize) -> &'a [u32] {
    match (off.get(i), off.get(i + 1)) {
        (Some(&a), Some(&b)) => data.get(a as usize..b as usize).unwrap_or(&[]),
        _ => &[],
    }
}

/// Producers and consumers are exactly the relation the FU rows give, as
/// [`super::Builder`] derives it: each object's producers are the FUs that output it (once
/// each, in increasing order; none for a bare object), its consumers the FUs that take it
/// as an input (once per input slot, in non-decreasing order). The searches rely on it (a
/// producer outputs its object). Checked in sequential scans, in parallel parts: the order
/// of each row, and equal multisets of (object, FU) pairs from both sides ([`PairSum`]).
/// The columns are read as slices once; every access is checked, so that bytes the other
/// checks refuse cannot make this one panic.
struct Adjacency<'a> {
    key: u64,
    states_off: &'a [u32],
    ingredients_off: &'a [u32],
    container: &'a [u32],
    prod_off: &'a [u32],
    prod: &'a [u32],
    cons_off: &'a [u32],
    cons: &'a [u32],
    in_off: &'a [u32],
    inputs: &'a [u32],
    out_off: &'a [u32],
    outputs: &'a [u32],
}

impl<'a> Adjacency<'a> {
    fn new(f: &'a Foon) -> Self {
        Self {
            key: pair_key(),
            states_off: &f.obj_states.off,
            ingredients_off: &f.obj_ingredients.off,
            container: &f.obj_container,
            prod_off: &f.producers.off,
            prod: &f.producers.data,
            cons_off: &f.consumers.off,
            cons: &f.consumers.data,
            in_off: &f.fu_inputs.off,
            inputs: &f.fu_inputs.data,
            out_off: &f.fu_outputs.off,
            outputs: &f.fu_outputs.data,
        }
    }

    /// As [`Foon::is_bare`], on the slices.
    #[inline]
    fn bare(&self, o: usize) -> bool {
        let empty = |off: &[u32]| match (off.get(o), off.get(o + 1)) {
            (Some(a), Some(b)) => a >= b,
            _ => true,
        };
        empty(self.states_off)
            && empty(self.ingredients_off)
            && self.container.get(o) == Some(&NONE)
    }

    /// The by-object sums (`[producers, consumers, 0, 0]`) of the objects in `r`.
    fn objects(&self, r: Range<usize>) -> std::result::Result<[PairSum; 4], String> {
        let mut s = [PairSum::default(); 4];
        for o in r {
            let p = row(self.prod_off, self.prod, o);
            if !p.is_empty() && self.bare(o) {
                return Err(format!(
                    "column producers lists FUs for the bare object {o}"
                ));
            }
            if p.windows(2).any(|w| w[1] <= w[0]) {
                return Err(format!("column producers is not increasing at object {o}"));
            }
            for &g in p {
                s[0].add(self.key, o as u32, g);
            }
            let c = row(self.cons_off, self.cons, o);
            if c.windows(2).any(|w| w[1] < w[0]) {
                return Err(format!("column consumers decreases at object {o}"));
            }
            for &g in c {
                s[1].add(self.key, o as u32, g);
            }
        }
        Ok(s)
    }

    /// The by-FU sums (`[0, 0, outputs, inputs]`) of the FUs in `r`.
    fn fus(&self, r: Range<usize>) -> [PairSum; 4] {
        let mut s = [PairSum::default(); 4];
        for g in r {
            let out = row(self.out_off, self.outputs, g);
            for (i, &o) in out.iter().enumerate() {
                if !self.bare(o as usize) && !out[..i].contains(&o) {
                    s[2].add(self.key, o, g as u32);
                }
            }
            for &o in row(self.in_off, self.inputs, g) {
                s[3].add(self.key, o, g as u32);
            }
        }
        s
    }
}

/// `work(k)` for `k` in `0..parts`, on scoped threads (one per core), in order.
fn par_parts<T: Send>(parts: u32, work: impl Fn(u32) -> T + Sync) -> Vec<T> {
    let workers = std::thread::available_parallelism()
        .map_or(1, std::num::NonZero::get)
        .min(parts as usize)
        .max(1);
    let next = AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<T>>> =
        (0..parts).map(|_| std::sync::Mutex::new(None)).collect();
    let run = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= parts as usize {
                break;
            }
            let r = work(i as u32);
            if let Ok(mut slot) = results[i].lock() {
                *slot = Some(r);
            }
        }
    };
    std::thread::scope(|s| {
        for _ in 1..workers {
            s.spawn(run);
        }
        run();
    });
    results
        .into_iter()
        .filter_map(|m| m.into_inner().ok().flatten())
        .collect()
}

/// The offsets `off[r]` of a CSR: the first is 0, none is below the one before, the last is
/// the data length.
fn csr(name: &str, off: &[u32], data_len: usize, r: Range<usize>) -> Res {
    if r.is_empty() {
        return Ok(());
    }
    if r.start == 0 && off[0] != 0 {
        return Err(format!("column {name}_off does not start at 0"));
    }
    // Pairs (i - 1, i) for i in r, i > 0: a branch-free pass, then the position if any.
    let lo = r.start.saturating_sub(1);
    let s = &off[lo..r.end];
    let down = s
        .iter()
        .zip(&s[1..])
        .fold(0u32, |d, (a, b)| d | u32::from(b < a));
    if down != 0 {
        let i = s.windows(2).position(|w| w[1] < w[0]).unwrap_or(0);
        return Err(format!("column {name}_off decreases at row {}", lo + i));
    }
    if r.end == off.len() {
        let last = off[off.len() - 1] as usize;
        if last != data_len {
            return Err(format!(
                "column {name}_off ends at {last}, but {name} has {data_len} entries"
            ));
        }
    }
    Ok(())
}

/// Every id of `col[r]` is below `bound`, or is "no value" where `none` allows it.
fn ids(name: &str, col: &[u32], bound: usize, none: bool, r: Range<usize>) -> Res {
    let s = &col[r.clone()];
    // A branch-free maximum first (ids are below `u32::MAX`, so `bound` fits): with `none`,
    // "no value" wraps to 0 and every other id moves up by one.
    let b = bound.min(u32::MAX as usize) as u32;
    let any_bad = if none {
        s.iter().fold(0, |m: u32, &x| m.max(x.wrapping_add(1))) > b
    } else {
        !s.is_empty() && s.iter().fold(0, |m: u32, &x| m.max(x)) >= b
    };
    if !any_bad {
        return Ok(());
    }
    let bad = |x: u32| (x as usize) >= bound && !(none && x == NONE);
    match s.iter().position(|&x| bad(x)) {
        Some(i) => Err(format!(
            "column {name} holds {} at position {}, out of range (there are {bound})",
            s[i],
            r.start + i
        )),
        None => Ok(()),
    }
}

fn flags(name: &str, col: &[u8], r: Range<usize>) -> Res {
    let s = &col[r.clone()];
    if s.iter().fold(0, |m: u8, &x| m.max(x)) <= 2 {
        return Ok(());
    }
    match s.iter().position(|&x| x > 2) {
        Some(i) => Err(format!(
            "column {name} holds {} at position {} (flags are 0, 1 or 2)",
            s[i],
            r.start + i
        )),
        None => Ok(()),
    }
}

/// The sources of the (source, line) pairs in `col[r]` (`r` starts at an even position, as
/// [`CHUNK`] is even).
fn also(col: &[u32], n_src: usize, r: Range<usize>) -> Res {
    let s = &col[r.clone()];
    match s.chunks_exact(2).position(|p| p[0] as usize >= n_src) {
        Some(i) => Err(format!(
            "column fu_also names source {} at pair {}, out of range (there are {n_src})",
            s[2 * i],
            r.start / 2 + i
        )),
        None => Ok(()),
    }
}

/// The size of a hash table: a power of two, or empty for no entries.
fn table_size(name: &str, slots: &[u32], n: usize) -> Res {
    if slots.is_empty() {
        return if n == 0 {
            Ok(())
        } else {
            Err(format!("column {name} is empty but there are {n} entries"))
        };
    }
    if !slots.len().is_power_of_two() {
        return Err(format!(
            "column {name} has {} slots, not a power of two",
            slots.len()
        ));
    }
    Ok(())
}

/// The entries of `slots[r]` are below `n` or empty; sets `empty` when one is empty.
fn table(name: &str, slots: &[u32], n: usize, r: Range<usize>, empty: &AtomicBool) -> Res {
    let s = &slots[r.clone()];
    // EMPTY is u32::MAX: it wraps to 0, every entry moves up by one.
    let b = n.min(u32::MAX as usize) as u32;
    let (top, has_empty) = s.iter().fold((0u32, 0u32), |(m, e), &x| {
        (m.max(x.wrapping_add(1)), e | u32::from(x == EMPTY))
    });
    if has_empty != 0 {
        empty.store(true, Ordering::Relaxed);
    }
    if top <= b {
        return Ok(());
    }
    match s.iter().position(|&x| x != EMPTY && x as usize >= n) {
        Some(i) => Err(format!(
            "column {name} holds {} at slot {}, out of range (there are {n})",
            s[i],
            r.start + i
        )),
        None => Ok(()),
    }
}

fn strings(name: &str, text: &[u8], ends: &[u64]) -> std::result::Result<(), String> {
    let Ok(s) = std::str::from_utf8(text) else {
        return Err(format!("column {name}_text is not UTF-8"));
    };
    if let Some(i) = ends.windows(2).position(|w| w[1] < w[0]) {
        return Err(format!("column {name}_ends decreases at string {i}"));
    }
    let last = ends.last().copied().unwrap_or(0);
    if last != text.len() as u64 {
        return Err(format!(
            "column {name}_ends ends at {last}, but {name}_text has {} bytes",
            text.len()
        ));
    }
    if let Some(i) = ends.iter().position(|&e| !s.is_char_boundary(e as usize)) {
        return Err(format!("column {name}_ends cuts a character at string {i}"));
    }
    Ok(())
}

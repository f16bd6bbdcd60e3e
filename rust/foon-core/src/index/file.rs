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
//! the element size of its id. It then checks in parallel the invariants that the search code
//! relies on, so that no later access can panic: CSR offsets start at 0, never decrease and
//! end at the data length; every id is in range (or "no value" where allowed); tables have a
//! power-of-two size, an empty slot and entries in range; string ends increase, fall on UTF-8
//! boundaries and the text is UTF-8. The data checksum is verified on request
//! ([`Foon::verify_checksum`]). Any failure is an [`Error::BadIndex`] naming the file and
//! what is wrong. The file carries the index only (columns, strings, sources and provenance),
//! not the load report: a FOON opened from a file has an empty report.
//!
//! A mapped file must not be changed while it is open (replace it by renaming a new file over
//! it, as [`Foon::write_index_file`] does); changing it in place is not supported. Big-endian
//! hosts are refused with a clear error (the columns are little-endian and used in place).

use std::borrow::Cow;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use std::sync::atomic::{AtomicUsize, Ordering};
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

/// Whether the file at `path` starts with the index magic (false when it cannot be read).
pub fn is_index_file(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 8];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && head == MAGIC
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

type Check<'a> = Box<dyn Fn() -> std::result::Result<(), String> + Sync + 'a>;

/// The lengths every column must have, then the invariants the search code relies on
/// (module documentation), scanned in parallel. The first failing check (in a fixed order)
/// is reported.
fn validate(f: &Foon) -> std::result::Result<(), String> {
    let n_str = f.strings.len();
    let n_obj = f.object_count();
    let n_var = f.var_obj.len();
    let n_fu = f.fu_count();
    let n_src = f.sources.len();
    let names: Vec<&str> = COLUMNS.iter().map(|c| c.0).collect();
    let cols = f.columns();
    let want_len = |name: &str, want: usize| -> std::result::Result<(), String> {
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
    let checks: Vec<Check<'_>> = vec![
        Box::new(|| strings("str", &f.strings.list.text, &f.strings.list.ends)),
        Box::new(|| strings("src", &f.sources.text, &f.sources.ends)),
        Box::new(|| csr("obj_states", &f.obj_states.off, f.obj_states.data.len())),
        Box::new(|| {
            csr(
                "obj_ingredients",
                &f.obj_ingredients.off,
                f.obj_ingredients.data.len(),
            )
        }),
        Box::new(|| csr("var_states", &f.var_states.off, f.var_states.data.len())),
        Box::new(|| {
            csr(
                "var_ingredients",
                &f.var_ingredients.off,
                f.var_ingredients.data.len(),
            )
        }),
        Box::new(|| csr("fu_inputs", &f.fu_inputs.off, f.fu_inputs.data.len())),
        Box::new(|| csr("fu_outputs", &f.fu_outputs.off, f.fu_outputs.data.len())),
        Box::new(|| csr("producers", &f.producers.off, f.producers.data.len())),
        Box::new(|| csr("consumers", &f.consumers.off, f.consumers.data.len())),
        Box::new(|| csr("fu_also", &f.fu_also.off, f.fu_also.data.len())),
        Box::new(|| ids("obj_label", &f.obj_label, n_str, false)),
        Box::new(|| ids("obj_container", &f.obj_container, n_str, true)),
        Box::new(|| ids("obj_states", &f.obj_states.data, n_str, false)),
        Box::new(|| ids("obj_ingredients", &f.obj_ingredients.data, n_str, false)),
        Box::new(|| ids("obj_first_variant", &f.obj_first_variant, n_var, false)),
        Box::new(|| ids("var_obj", &f.var_obj, n_obj, false)),
        Box::new(|| ids("var_states", &f.var_states.data, n_str, false)),
        Box::new(|| ids("var_ingredients", &f.var_ingredients.data, n_str, false)),
        Box::new(|| ids("fu_motion", &f.fu_motion, n_str, false)),
        Box::new(|| ids("fu_motion_meta", &f.fu_motion_meta, n_str, true)),
        Box::new(|| ids("fu_inputs", &f.fu_inputs.data, n_obj, false)),
        Box::new(|| ids("fu_outputs", &f.fu_outputs.data, n_obj, false)),
        Box::new(|| ids("fu_input_variant", &f.fu_input_variant, n_var, false)),
        Box::new(|| ids("fu_output_variant", &f.fu_output_variant, n_var, false)),
        Box::new(|| flags("fu_input_in_motion", &f.fu_input_in_motion)),
        Box::new(|| flags("fu_output_in_motion", &f.fu_output_in_motion)),
        Box::new(|| ids("producers", &f.producers.data, n_fu, false)),
        Box::new(|| ids("consumers", &f.consumers.data, n_fu, false)),
        Box::new(|| ids("motions", &f.motions, n_str, false)),
        Box::new(|| ids("fu_source", &f.fu_source, n_src, false)),
        Box::new(|| also(&f.fu_also.data, n_src)),
        Box::new(|| table("str_table", &f.strings.table.slots, n_str)),
        Box::new(|| table("obj_table", &f.obj_table.slots, n_obj)),
        Box::new(|| table("fu_table", &f.fu_table.slots, n_fu)),
    ];
    run_all(&checks)?;
    // Then the adjacency (it reads rows through the ids checked above).
    adjacency(f)
}

fn chunk(n: u32, parts: u32, k: u32) -> u32 {
    (u64::from(n) * u64::from(k) / u64::from(parts)) as u32
}

/// Runs the checks on scoped threads (one per core, each taking the next check), and
/// reports the first failure in list order. Scoped threads end with the call: nothing is
/// left running (a process forked afterwards, as `multiprocessing` does, is unaffected).
fn run_all(checks: &[Check<'_>]) -> std::result::Result<(), String> {
    par_parts(checks.len() as u32, |i| checks[i as usize]())
        .into_iter()
        .collect()
}

/// Sums of a keyed mix of `(object, FU)` pairs: equal multisets of pairs give equal sums;
/// unequal ones, unequal sums but with a negligible probability (the keys are random per
/// process, so a file cannot be made to collide on purpose).
#[derive(Clone, Copy, Default, PartialEq, Eq)]
struct PairSum(u64, u64);

impl PairSum {
    #[inline]
    fn add(&mut self, keys: (u64, u64), o: u32, f: u32) {
        let x = (u64::from(o) << 32) | u64::from(f);
        self.0 = self.0.wrapping_add(mix(x ^ keys.0));
        self.1 = self.1.wrapping_add(mix(x.rotate_left(17) ^ keys.1));
    }

    fn merge(self, o: Self) -> Self {
        Self(self.0.wrapping_add(o.0), self.1.wrapping_add(o.1))
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

/// Per-process random keys for [`PairSum`].
fn pair_keys() -> (u64, u64) {
    use std::hash::{BuildHasher, Hasher};
    let s = std::collections::hash_map::RandomState::new();
    let mut a = s.build_hasher();
    a.write_u64(1);
    let mut b = s.build_hasher();
    b.write_u64(2);
    (a.finish(), b.finish())
}

/// Producers and consumers are exactly the relation the FU rows give, as
/// [`super::Builder`] derives it: each object's producers are the FUs that output it (once
/// each, in increasing order; none for a bare object), its consumers the FUs that take it
/// as an input (once per input slot, in non-decreasing order). The searches rely on it (a
/// producer outputs its object). Checked in sequential scans, in parallel parts: the order
/// of each row, and equal multisets of (object, FU) pairs from both sides ([`PairSum`]).
fn adjacency(f: &Foon) -> std::result::Result<(), String> {
    const PARTS: u32 = 16;
    let keys = pair_keys();
    let n_obj = f.object_count() as u32;
    let n_fu = f.fu_count() as u32;
    let bare: Vec<bool> = (0..n_obj).map(|o| f.is_bare(o)).collect();
    let sums = par_parts(PARTS, |k| {
        // [producers by object, consumers by object, producers by FU, consumers by FU]
        let mut s = [PairSum::default(); 4];
        for o in chunk(n_obj, PARTS, k)..chunk(n_obj, PARTS, k + 1) {
            let p = f.producers.row(o);
            if !p.is_empty() && bare[o as usize] {
                return Err(format!(
                    "column producers lists FUs for the bare object {o}"
                ));
            }
            if p.windows(2).any(|w| w[1] <= w[0]) {
                return Err(format!("column producers is not increasing at object {o}"));
            }
            for &g in p {
                s[0].add(keys, o, g);
            }
            let c = f.consumers.row(o);
            if c.windows(2).any(|w| w[1] < w[0]) {
                return Err(format!("column consumers decreases at object {o}"));
            }
            for &g in c {
                s[1].add(keys, o, g);
            }
        }
        for g in chunk(n_fu, PARTS, k)..chunk(n_fu, PARTS, k + 1) {
            let out = f.fu_outputs.row(g);
            for (i, &o) in out.iter().enumerate() {
                if !bare[o as usize] && !out[..i].contains(&o) {
                    s[2].add(keys, o, g);
                }
            }
            f.fu_inputs
                .row(g)
                .iter()
                .for_each(|&o| s[3].add(keys, o, g));
        }
        Ok(s)
    });
    let mut total = [PairSum::default(); 4];
    for part in sums {
        for (t, x) in total.iter_mut().zip(part?) {
            *t = t.merge(x);
        }
    }
    if total[0] != total[2] {
        return Err("column producers does not match the FU outputs".into());
    }
    if total[1] != total[3] {
        return Err("column consumers does not match the FU inputs".into());
    }
    Ok(())
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

fn csr(name: &str, off: &[u32], data_len: usize) -> std::result::Result<(), String> {
    if off.is_empty() {
        return Ok(());
    }
    if off[0] != 0 {
        return Err(format!("column {name}_off does not start at 0"));
    }
    if let Some(i) = off.windows(2).position(|w| w[1] < w[0]) {
        return Err(format!("column {name}_off decreases at row {i}"));
    }
    let last = off[off.len() - 1] as usize;
    if last != data_len {
        return Err(format!(
            "column {name}_off ends at {last}, but {name} has {data_len} entries"
        ));
    }
    Ok(())
}

fn ids(name: &str, col: &[u32], bound: usize, none: bool) -> std::result::Result<(), String> {
    let bad = |x: u32| (x as usize) >= bound && !(none && x == NONE);
    match col.iter().position(|&x| bad(x)) {
        Some(i) => Err(format!(
            "column {name} holds {} at position {i}, out of range (there are {bound})",
            col[i]
        )),
        None => Ok(()),
    }
}

fn flags(name: &str, col: &[u8]) -> std::result::Result<(), String> {
    match col.iter().position(|&x| x > 2) {
        Some(i) => Err(format!(
            "column {name} holds {} at position {i} (flags are 0, 1 or 2)",
            col[i]
        )),
        None => Ok(()),
    }
}

fn also(col: &[u32], n_src: usize) -> std::result::Result<(), String> {
    if col.len() % 2 != 0 {
        return Err("column fu_also has an odd length (it holds (source, line) pairs)".into());
    }
    match col.chunks_exact(2).position(|p| p[0] as usize >= n_src) {
        Some(i) => Err(format!(
            "column fu_also names source {} at pair {i}, out of range (there are {n_src})",
            col[2 * i]
        )),
        None => Ok(()),
    }
}

fn table(name: &str, slots: &[u32], n: usize) -> std::result::Result<(), String> {
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
    if let Some(i) = slots.iter().position(|&x| x != EMPTY && x as usize >= n) {
        return Err(format!(
            "column {name} holds {} at slot {i}, out of range (there are {n})",
            slots[i]
        ));
    }
    if !slots.contains(&EMPTY) {
        return Err(format!("column {name} has no empty slot"));
    }
    Ok(())
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

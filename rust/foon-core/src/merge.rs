//! Merging many FOONs into one, with provenance and support.
//!
//! [`merge_files`] (and [`merge_sources`], for text in memory) reads its sources in the order
//! given (any mix of dialects: FOON text and the lab's JSON), builds one index of them and
//! drops the functional units (FUs) that repeat an earlier one at the chosen identity level.
//! A kept FU is the first copy met; it records every (source, line) it was found at, in
//! reading order, and its *support*, the number of distinct sources that contain it. With a
//! minimum support K, only the FUs found in at least K sources are kept (and the objects that
//! no kept FU uses are gone). A folder stands for its `.txt` and `.json` files (not those of
//! its subfolders), sorted by name ([`expand_paths`]).
//!
//! # Identity levels
//!
//! The levels follow the FOON hierarchy levels of the lab's FOON code (Paulius et al. 2018;
//! `equals_lvl1/2/3` of its `Object` and `FunctionalUnit` classes). Two FUs are the same at
//! level L when they have the same motion label, the same multiset of input objects and the
//! same multiset of output objects, objects compared at level L:
//!
//! | level | two objects are the same when they have the same ... |
//! |---|---|
//! | 3 (default) | label, multiset of plain states, multiset of ingredients and container (full identity, SEMANTICS.md §2) |
//! | 2 | label, multiset of plain states and container; ingredients are ignored |
//! | 1 | label; states, ingredients and container are ignored |
//!
//! The lab's level 2 compares each state with its related object (`in [bowl]`), that is, the
//! container; so does ours. Unlike the lab's code, a list that names the same object twice
//! keeps both copies at every level (lists are multisets, as on load), and motions are compared
//! by label (the lab compares motion ids). The level only decides which FUs are duplicates: a
//! kept FU keeps the objects of its first copy in full, so a merge at level 1 or 2 is still a
//! FOON of full objects that plans as any other.
//!
//! # Output
//!
//! [`merged_text`] writes the merged FOON as FOON text in the course form, with the provenance
//! as comment lines (every FOON reader skips lines that start with `#`; a TAB follows the
//! marker, so that the course parser, which warns about lines without one, passes over them
//! silently):
//!
//! ```text
//! # foon merge:<TAB>level 3, min support 1, 2 sources, 3 units kept
//! # input:<TAB>a.txt
//! # input:<TAB>b.txt
//! # source:<TAB>a.txt:1
//! # source:<TAB>b.txt:7
//! O<TAB>egg
//! ...
//! //
//! ```
//!
//! One `# input:` line per source, in reading order; before each FU, one `# source:` line per
//! origin, in reading order (its kept copy first). A path is written with `\` as `\\`, TAB as
//! `\t`, CR as `\r` and LF as `\n`. [`parse_merged`] reads such a file back with the same FUs
//! and the same provenance.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rustc_hash::{FxHashMap, FxHashSet};

use crate::error::{Error, InputKind, Result, WarningKind};
use crate::index::{Builder, Foon, NONE, RawObject};
use crate::parse::{ParseOptions, parse_into};
use crate::progress::Progress;

/// How to merge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MergeOptions {
    /// Identity level (1, 2 or 3; see the module documentation).
    pub level: u8,
    /// Keep only the FUs found in at least this many distinct sources (at least 1).
    pub min_support: u32,
    /// Turn every load warning into an error.
    pub strict: bool,
}

impl Default for MergeOptions {
    fn default() -> Self {
        Self {
            level: 3,
            min_support: 1,
            strict: false,
        }
    }
}

impl MergeOptions {
    /// Checks the options: a clear error for a level outside 1–3 or a support of 0.
    pub fn check(&self) -> Result<()> {
        if !(1..=3).contains(&self.level) {
            return Err(Error::Invalid(format!(
                "merge level must be 1, 2 or 3 (got {})",
                self.level
            )));
        }
        if self.min_support == 0 {
            return Err(Error::Invalid(
                "minimum support must be at least 1".to_owned(),
            ));
        }
        Ok(())
    }
}

/// What a merge read, kept and dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MergeReport {
    /// Sources read.
    pub sources: usize,
    /// FUs read (every complete FU of every source, duplicates included, faulty ones not).
    pub units_read: usize,
    /// FUs dropped for an annotation fault (no motion line, two motion lines), with a warning.
    pub faulty: usize,
    /// FUs dropped because they repeat an earlier FU exactly (full identity).
    pub duplicates: usize,
    /// FUs dropped because they repeat an earlier FU at the chosen level only (0 at level 3).
    pub same_at_level: usize,
    /// Distinct FUs (at the level) dropped because fewer sources than the minimum hold them.
    pub below_support: usize,
    /// FUs kept.
    pub kept: usize,
    /// Objects of the merged FOON.
    pub objects: usize,
    /// Distinct motions of the merged FOON.
    pub motions: usize,
}

/// A merged FOON and its report.
#[derive(Debug, Clone)]
pub struct Merged {
    pub foon: Foon,
    pub report: MergeReport,
    pub options: MergeOptions,
    /// The files read, in order (empty for sources given in memory).
    pub inputs: Vec<PathBuf>,
}

/// Whether `path` names a FOON file a folder expands to (`.txt` or `.json`, any case).
fn is_foon_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("txt") || e.eq_ignore_ascii_case("json"))
}

/// The files to read for `paths`, in order: a file as it is, a folder as its FOON files
/// (`.txt` and `.json`, not in subfolders) sorted by name. A folder without one, or a path
/// given twice (also through a folder), is an error.
pub fn expand_paths(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| Error::io(p, e))?;
        if meta.is_dir() {
            let mut files = Vec::new();
            for entry in std::fs::read_dir(p).map_err(|e| Error::io(p, e))? {
                let entry = entry.map_err(|e| Error::io(p, e))?;
                let path = entry.path();
                if !is_foon_file(&path) {
                    continue;
                }
                let kind = entry.file_type().map_err(|e| Error::io(&path, e))?;
                if kind.is_file() || (kind.is_symlink() && path.is_file()) {
                    files.push(path);
                }
            }
            if files.is_empty() {
                return Err(Error::Invalid(format!(
                    "{}: no FOON files (.txt, .json) in this folder",
                    p.display()
                )));
            }
            files.sort();
            out.extend(files);
        } else {
            out.push(p.clone());
        }
    }
    let mut seen = FxHashMap::default();
    for p in &out {
        if let Some(first) = seen.insert(crate::atomic::file_key(p)?, p) {
            return Err(Error::Invalid(format!(
                "{} is given twice (as {} and {})",
                p.display(),
                first.display(),
                p.display()
            )));
        }
    }
    Ok(out)
}

/// Merges the files and folders `paths` (see [`expand_paths`]); `cancel` is asked now and then
/// and stops the merge with [`Error::Cancelled`].
pub fn merge_files(
    paths: &[PathBuf],
    opts: MergeOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Merged> {
    merge_files_with(paths, opts, cancel, None)
}

/// As [`merge_files`], counting the files read in `progress` (phase `merge`).
pub fn merge_files_with(
    paths: &[PathBuf],
    opts: MergeOptions,
    cancel: &(dyn Fn() -> bool + Sync),
    progress: Option<&Progress>,
) -> Result<Merged> {
    opts.check()?;
    let files = expand_paths(paths)?;
    if let Some(p) = progress {
        p.begin("merge", files.len() as u64);
    }
    let mut b = Builder::new();
    for f in &files {
        if cancel() {
            return Err(Error::Cancelled);
        }
        let popts = ParseOptions {
            strict: opts.strict,
        };
        let ctl = crate::parse::ParseControl::default();
        crate::parse::load_into(&mut b, f, popts, None, cancel, ctl)?;
        if let Some(p) = progress {
            p.add(1);
        }
    }
    let mut m = finish(b, files.len(), opts);
    m.inputs = files;
    Ok(m)
}

/// Merges sources given in memory as (name, bytes), in order; names must be distinct.
pub fn merge_sources(
    sources: &[(&Path, &[u8])],
    opts: MergeOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Merged> {
    opts.check()?;
    let mut names = FxHashSet::default();
    for (name, _) in sources {
        if !names.insert(*name) {
            return Err(Error::Invalid(format!("{} is given twice", name.display())));
        }
    }
    let mut b = Builder::new();
    for (name, data) in sources {
        read_source(&mut b, data, name, opts, cancel)?;
    }
    Ok(finish(b, sources.len(), opts))
}

/// Parses one source into `b`.
fn read_source(
    b: &mut Builder,
    data: &[u8],
    path: &Path,
    opts: MergeOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
    let popts = ParseOptions {
        strict: opts.strict,
    };
    parse_into(b, data, Some(path), popts, None, cancel)
}

/// Collapses the level-3 index `b` at the level, applies the minimum support and counts.
fn finish(b: Builder, sources: usize, opts: MergeOptions) -> Merged {
    let full = b.finish();
    let faulty = full
        .warnings()
        .iter()
        .filter(|w| matches!(w.kind, WarningKind::NoMotion | WarningKind::TwoMotions))
        .count();
    let duplicates = full.duplicates().len();
    let units_read = full.fu_count() + duplicates;
    let groups = groups(&full, opts.level);
    let same_at_level = full.fu_count() - groups.len();
    let mut kept_groups = Vec::with_capacity(groups.len());
    let mut below_support = 0;
    for g in groups {
        if support_of(&g.origins) >= opts.min_support as usize {
            kept_groups.push(g);
        } else {
            below_support += 1;
        }
    }
    let foon = if opts.level == 3 && below_support == 0 {
        full
    } else {
        rebuild(&full, &kept_groups, &source_names(&full))
    };
    let report = MergeReport {
        sources,
        units_read,
        faulty,
        duplicates,
        same_at_level,
        below_support,
        kept: foon.fu_count(),
        objects: foon.object_count(),
        motions: foon.motion_ids().len(),
    };
    Merged {
        foon,
        report,
        options: opts,
        inputs: Vec::new(),
    }
}

/// FUs equal at a level: the first member (the kept FU) and every origin of every member, in
/// reading order.
struct Group {
    first: u32,
    origins: Vec<(u32, u32)>,
}

fn support_of(origins: &[(u32, u32)]) -> usize {
    let mut s: Vec<u32> = origins.iter().map(|o| o.0).collect();
    s.sort_unstable();
    s.dedup();
    s.len()
}

/// The identity of an object at level 1 or 2 (see the module documentation), from its
/// label, container (`NONE` for none) and states (a multiset sorted by string id), all string
/// ids of one FOON: (label, container, states) at level 2, (label, `NONE`, no state) at
/// level 1. Two objects are the same at the level exactly when their keys are equal. The one
/// definition of a level below full identity, for merging and for matching kitchens and goals
/// ([`Kitchen::match_at_level`](crate::Kitchen::match_at_level)).
pub fn level_key(level: u8, label: u32, container: u32, states: &[u32]) -> (u32, u32, &[u32]) {
    if level <= 1 {
        (label, crate::index::NONE, &[])
    } else {
        (label, container, states)
    }
}

/// The level key of object `o` of `foon` at level 1 or 2 ([`level_key`]).
pub fn object_level_key(foon: &Foon, level: u8, o: u32) -> (u32, u32, &[u32]) {
    level_key(level, foon.label(o), foon.container(o), foon.states(o))
}

/// The level key of each object of `foon`: objects equal at `level` get the same key.
fn object_keys(foon: &Foon, level: u8) -> Vec<u32> {
    let n = foon.object_count() as u32;
    if level == 3 {
        return (0..n).collect();
    }
    let mut ids: FxHashMap<(u32, u32, &[u32]), u32> = FxHashMap::default();
    (0..n)
        .map(|o| {
            let next = ids.len() as u32;
            *ids.entry(object_level_key(foon, level, o)).or_insert(next)
        })
        .collect()
}

/// The FUs of `foon` grouped by identity at `level`, groups in the order of their first FU.
fn groups(foon: &Foon, level: u8) -> Vec<Group> {
    let n = foon.fu_count() as u32;
    let origins = |f: u32| foon.origins(f);
    if level == 3 {
        return (0..n)
            .map(|f| Group {
                first: f,
                origins: origins(f).collect(),
            })
            .collect();
    }
    let keys = object_keys(foon, level);
    let mut index: FxHashMap<Vec<u32>, usize> = FxHashMap::default();
    let mut out: Vec<Group> = Vec::new();
    for f in 0..n {
        let mut key = vec![foon.motion(f), foon.inputs(f).len() as u32];
        key.extend(foon.inputs(f).iter().map(|&o| keys[o as usize]));
        key[2..].sort_unstable();
        let s = key.len();
        key.extend(foon.outputs(f).iter().map(|&o| keys[o as usize]));
        key[s..].sort_unstable();
        if let Some(&g) = index.get(&key) {
            out[g].origins.extend(origins(f));
        } else {
            index.insert(key, out.len());
            out.push(Group {
                first: f,
                origins: origins(f).collect(),
            });
        }
    }
    for g in &mut out {
        g.origins.sort_unstable();
    }
    out
}

/// Interns the strings of one FOON into a builder, each once.
struct Strings<'a> {
    from: &'a Foon,
    map: Vec<u32>,
}

impl Strings<'_> {
    fn get(&mut self, b: &mut Builder, id: u32) -> u32 {
        if id == NONE {
            return NONE;
        }
        let i = id as usize;
        if self.map.len() <= i {
            self.map.resize(i + 1, NONE);
        }
        if self.map[i] == NONE {
            self.map[i] = b.intern(self.from.text(id));
        }
        self.map[i]
    }
}

/// An object as written: label, states, ingredients, container, in-motion flag.
type Obj = (u32, Vec<u32>, Vec<u32>, u32, u8);

/// The builder's view of an [`Obj`].
fn raw(t: &Obj) -> RawObject<'_> {
    RawObject {
        label: t.0,
        states: &t.1,
        ingredients: &t.2,
        container: t.3,
        in_motion: t.4,
    }
}

/// Copies FU `f` of `from` into `b` (its objects as written, its motion and metadata) with
/// `line` as its line; returns its index in `b`.
fn copy_fu(b: &mut Builder, strings: &mut Strings<'_>, f: u32, line: u32) -> u32 {
    let from = strings.from;
    let side = |b: &mut Builder, strings: &mut Strings<'_>, vars: &[u32], flags: &[u8]| {
        vars.iter()
            .enumerate()
            .map(|(k, &v)| {
                let o = from.variant_object(v);
                let label = strings.get(b, from.label(o));
                let states = from
                    .variant_states(v)
                    .iter()
                    .map(|&s| strings.get(b, s))
                    .collect();
                let ingredients = from
                    .variant_ingredients(v)
                    .iter()
                    .map(|&s| strings.get(b, s))
                    .collect();
                let container = strings.get(b, from.container(o));
                let flag = flags.get(k).copied().unwrap_or(0);
                (label, states, ingredients, container, flag)
            })
            .collect::<Vec<Obj>>()
    };
    let ins = side(b, strings, from.input_variants(f), from.input_in_motion(f));
    let outs = side(
        b,
        strings,
        from.output_variants(f),
        from.output_in_motion(f),
    );
    let ri: Vec<RawObject<'_>> = ins.iter().map(raw).collect();
    let ro: Vec<RawObject<'_>> = outs.iter().map(raw).collect();
    let motion = strings.get(b, from.motion(f));
    let meta = from.motion_meta(f).map_or(NONE, |m| b.intern(m));
    match b.add_fu(motion, meta, &ri, &ro, line) {
        Ok(i) | Err(i) => i,
    }
}

/// A new index holding the first FU of each group with the group's origins (the first one is
/// its kept copy); source `i` is named `names[i]`. The groups come in reading order, so the
/// sources of their kept copies never go back.
fn rebuild(from: &Foon, groups: &[Group], names: &[String]) -> Foon {
    let mut b = Builder::new();
    let mut strings = Strings {
        from,
        map: Vec::new(),
    };
    let mut begun = 0usize;
    let begin_until = |b: &mut Builder, begun: &mut usize, s: usize| {
        while *begun <= s && *begun < names.len() {
            let name = names[*begun].as_str();
            b.begin_source((!name.is_empty()).then(|| Path::new(name)));
            *begun += 1;
        }
    };
    for g in groups {
        let (source, line) = g.origins[0];
        begin_until(&mut b, &mut begun, source as usize);
        let idx = copy_fu(&mut b, &mut strings, g.first, line);
        for &(s, l) in &g.origins[1..] {
            b.add_origin(idx, s, l);
        }
    }
    begin_until(&mut b, &mut begun, names.len());
    for w in from.warnings() {
        b.warn(w.clone());
    }
    for w in from.notes() {
        b.note(w.clone());
    }
    b.finish()
}

/// The source names of `foon`, by id.
fn source_names(foon: &Foon) -> Vec<String> {
    (0..foon.source_count() as u32)
        .map(|s| foon.source_name(s).to_owned())
        .collect()
}

/// Writes a path on one line: `\` as `\\`, TAB as `\t`, CR as `\r`, LF as `\n`.
fn escape(s: &str, out: &mut String) {
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
}

fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut it = s.chars();
    while let Some(c) = it.next() {
        if c == '\\' {
            match it.next() {
                Some('t') => out.push('\t'),
                Some('r') => out.push('\r'),
                Some('n') => out.push('\n'),
                Some(other) => out.push(other),
                None => out.push('\\'),
            }
        } else {
            out.push(c);
        }
    }
    out
}

const HEADER: &str = "# foon merge:\t";
const INPUT: &str = "# input:\t";
const SOURCE: &str = "# source:\t";

/// The merged FOON as FOON text with its provenance as comment lines (see the module
/// documentation); `header` (one line, no newline) follows the `# foon merge:` marker.
pub fn merged_text(foon: &Foon, header: &str) -> String {
    let mut out = String::new();
    out.push_str(HEADER);
    out.push_str(&header.replace(['\n', '\r'], " "));
    out.push('\n');
    for s in 0..foon.source_count() as u32 {
        out.push_str(INPUT);
        escape(foon.source_name(s), &mut out);
        out.push('\n');
    }
    for f in 0..foon.fu_count() as u32 {
        for (s, l) in foon.origins(f) {
            out.push_str(SOURCE);
            escape(foon.source_name(s), &mut out);
            let _ = writeln!(out, ":{l}");
        }
        crate::write::fu_text(foon, f, &mut out);
        out.push('\n');
    }
    out
}

/// The one-line header [`merged_text`] is given by [`write_merged`].
pub fn header_line(m: &Merged) -> String {
    format!(
        "level {}, min support {}, {} sources, {} units kept",
        m.options.level, m.options.min_support, m.report.sources, m.report.kept
    )
}

/// Writes `text` to `out` atomically (see [`crate::atomic`]), refusing an output that is one
/// of `inputs`.
pub fn write_atomic(out: &Path, text: &[u8], inputs: &[PathBuf]) -> Result<()> {
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    crate::atomic::write_atomic(out, &inputs, |w| crate::write::put(w, text))
}

/// Writes the merged FOON to `out`, atomically, refusing an output that is one of the files
/// read: as text with provenance (see [`merged_text`]), or as an index file (provenance in its
/// columns) when `out` ends in `.foonidx`.
pub fn write_merged(m: &Merged, out: &Path) -> Result<()> {
    if out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("foonidx"))
    {
        return m.foon.write_index_file(out);
    }
    let text = merged_text(&m.foon, &header_line(m));
    write_atomic(out, text.as_bytes(), &m.inputs)
}

/// Parses FOON text and, when it has the provenance comments of [`merged_text`], gives each FU
/// the sources and lines they name (FOON text without them parses as usual). Provenance that
/// cannot be read is an error naming its line.
pub fn parse_merged(data: &[u8], path: Option<&Path>, opts: ParseOptions) -> Result<Foon> {
    let mut b = Builder::new();
    parse_into(&mut b, data, path, opts, None, &|| false)?;
    let plain = b.finish();
    let text = String::from_utf8_lossy(data);
    let mut inputs: Vec<String> = Vec::new();
    // Origins named by the comment lines just above line L (the first line of an FU).
    let mut at: FxHashMap<u32, Vec<(String, u32)>> = FxHashMap::default();
    let mut pending: Vec<(String, u32)> = Vec::new();
    for (i, line) in text.split('\n').enumerate() {
        let number = i as u32 + 1;
        let line = line.strip_suffix('\r').unwrap_or(line);
        if let Some(p) = line.strip_prefix(INPUT) {
            inputs.push(unescape(p));
        } else if let Some(rest) = line.strip_prefix(SOURCE) {
            let parsed = rest
                .rsplit_once(':')
                .and_then(|(p, l)| Some((unescape(p), l.parse::<u32>().ok()?)));
            let Some(origin) = parsed else {
                return Err(Error::parse(
                    InputKind::Foon,
                    path,
                    u64::from(number),
                    1,
                    "a source comment must end with ':' and a line number",
                ));
            };
            pending.push(origin);
        } else if !line.starts_with('#') && !line.trim().is_empty() && !pending.is_empty() {
            at.insert(number, std::mem::take(&mut pending));
        }
    }
    if inputs.is_empty() && at.is_empty() {
        return Ok(plain);
    }
    // Source ids: the inputs in order, then any other path named, in first-seen order.
    let mut ids: FxHashMap<String, u32> = FxHashMap::default();
    let mut names: Vec<String> = Vec::new();
    let mut id_of = |p: &str, ids: &mut FxHashMap<String, u32>| -> u32 {
        if let Some(&i) = ids.get(p) {
            return i;
        }
        let i = names.len() as u32;
        names.push(p.to_owned());
        ids.insert(p.to_owned(), i);
        i
    };
    for p in &inputs {
        id_of(p, &mut ids);
    }
    let n = plain.fu_count() as u32;
    let mut fu_origins: Vec<Vec<(u32, u32)>> = Vec::with_capacity(n as usize);
    let own = path
        .map(|p| p.to_string_lossy().into_owned())
        .unwrap_or_default();
    for f in 0..n {
        let line = plain.fu_line(f);
        let list = match at.get(&line) {
            Some(list) => list.iter().map(|(p, l)| (id_of(p, &mut ids), *l)).collect(),
            None => vec![(id_of(&own, &mut ids), line)],
        };
        fu_origins.push(list);
    }
    let mut last = 0;
    for (f, o) in fu_origins.iter().enumerate() {
        let s = o[0].0;
        if s < last {
            return Err(Error::parse(
                InputKind::Foon,
                path,
                u64::from(plain.fu_line(f as u32)),
                1,
                "the source comments of this unit are not in reading order \
                 (its first source comes before the previous unit's)",
            ));
        }
        last = s;
    }
    let groups: Vec<Group> = fu_origins
        .into_iter()
        .enumerate()
        .map(|(f, origins)| Group {
            first: f as u32,
            origins,
        })
        .collect();
    Ok(rebuild(&plain, &groups, &names))
}

/// Every (source path, line) where FU `fu` was found, in reading order (its kept copy first).
pub fn sources_of(foon: &Foon, fu: u32) -> Vec<(&str, u32)> {
    if fu as usize >= foon.fu_count() {
        return Vec::new();
    }
    foon.origins(fu)
        .map(|(s, l)| (foon.source_name(s), l))
        .collect()
}

/// Where each FU came from, one line per FU: `unit I: support N: path:line, path:line`
/// (the text of `foon stats --provenance`).
pub fn provenance_text(foon: &Foon) -> String {
    let mut out = String::new();
    for f in 0..foon.fu_count() as u32 {
        let _ = write!(out, "unit {f}: support {}: ", foon.support(f));
        for (k, (s, l)) in sources_of(foon, f).into_iter().enumerate() {
            if k > 0 {
                out.push_str(", ");
            }
            let name = if s.is_empty() { "<text>" } else { s };
            let _ = write!(out, "{name}:{l}");
        }
        out.push('\n');
    }
    out
}

impl Merged {
    /// The one-line summary `foon merge` prints.
    pub fn summary(&self) -> String {
        let r = &self.report;
        let o = &self.options;
        let mut s = format!(
            "merged {} sources at level {}: {} units read, {} kept ({} objects, {} motions); \
             dropped: {} faulty, {} duplicates",
            r.sources, o.level, r.units_read, r.kept, r.objects, r.motions, r.faulty, r.duplicates
        );
        if o.level < 3 {
            let _ = write!(s, ", {} equal at level {}", r.same_at_level, o.level);
        }
        if o.min_support > 1 {
            let _ = write!(s, ", {} below support {}", r.below_support, o.min_support);
        }
        s
    }
}

/// Reads a file and parses it with [`parse_merged`]; an index file is opened (its provenance is
/// in its columns).
pub fn load_merged(path: &Path, opts: ParseOptions) -> Result<Foon> {
    if crate::index::file::is_index_file(path) {
        return Foon::open_index(path); // its provenance is in its columns
    }
    let data = crate::parse::read_file(path)?;
    parse_merged(&data, Some(path), opts)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::{MergeOptions, merge_sources, merged_text, parse_merged, sources_of};
    use crate::parse::ParseOptions;

    const EGG: &str = "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n";
    /// EGG with a bowl holding the egg (ingredients), then with a different ingredient list.
    const EGG_IN_BOWL: &str = "O\tbowl\nS\tcontains\t{egg}\nM\tcrack\nO\tbowl\nS\tfull\n//\n";
    const EGG_IN_BOWL2: &str = "O\tbowl\nS\tcontains\t{egg,salt}\nM\tcrack\nO\tbowl\nS\tfull\n//\n";
    const EGG_HOT: &str = "O\tegg\nS\thot\nM\tcrack\nO\tegg\nS\tcracked\n//\n";

    fn opts(level: u8, min_support: u32) -> MergeOptions {
        MergeOptions {
            level,
            min_support,
            strict: false,
        }
    }

    fn run(sources: &[(&str, String)], o: MergeOptions) -> super::Merged {
        let refs: Vec<(&Path, &[u8])> = sources
            .iter()
            .map(|(n, t)| (Path::new(*n), t.as_bytes()))
            .collect();
        merge_sources(&refs, o, &|| false).unwrap()
    }

    fn sources() -> Vec<(&'static str, String)> {
        vec![
            ("a.txt", format!("{EGG}{EGG_IN_BOWL}")),
            ("b.txt", format!("{EGG_IN_BOWL2}{EGG}{EGG_HOT}")),
            ("c.txt", EGG.to_owned()),
        ]
    }

    #[test]
    fn level_3_keeps_first_copies_with_every_origin() {
        let m = run(&sources(), opts(3, 1));
        let f = &m.foon;
        assert_eq!(f.fu_count(), 4);
        assert_eq!(sources_of(f, 0), [("a.txt", 1), ("b.txt", 7), ("c.txt", 1)]);
        assert_eq!((f.support(0), f.support(1), f.support(2)), (3, 1, 1));
        assert_eq!(m.report.units_read, 6);
        assert_eq!((m.report.duplicates, m.report.same_at_level), (2, 0));
    }

    #[test]
    fn level_2_ignores_ingredients_and_level_1_states() {
        let m2 = run(&sources(), opts(2, 1));
        assert_eq!(m2.foon.fu_count(), 3);
        assert_eq!(sources_of(&m2.foon, 1), [("a.txt", 7), ("b.txt", 1)]);
        assert_eq!(m2.report.same_at_level, 1);
        let m1 = run(&sources(), opts(1, 1));
        assert_eq!(m1.foon.fu_count(), 2);
        assert_eq!(
            sources_of(&m1.foon, 0),
            [("a.txt", 1), ("b.txt", 7), ("b.txt", 13), ("c.txt", 1)]
        );
        // The kept unit is the first copy, in full.
        let mut s = String::new();
        crate::write::fu_text(&m1.foon, 1, &mut s);
        assert!(s.contains("{egg}"), "{s}");
    }

    #[test]
    fn min_support_drops_units_and_their_objects() {
        let m = run(&sources(), opts(3, 2));
        assert_eq!(m.foon.fu_count(), 1);
        assert_eq!(m.report.below_support, 3);
        assert_eq!(m.foon.object_count(), 2);
        assert_eq!(m.foon.source_count(), 3);
    }

    #[test]
    fn text_round_trip() {
        let m = run(&sources(), opts(2, 1));
        let text = merged_text(&m.foon, "test");
        let back = parse_merged(
            text.as_bytes(),
            Some(Path::new("m.txt")),
            ParseOptions::default(),
        )
        .unwrap();
        assert_eq!(back.fu_count(), m.foon.fu_count());
        assert_eq!(back.source_count(), 3);
        for f in 0..back.fu_count() as u32 {
            assert_eq!(sources_of(&back, f), sources_of(&m.foon, f));
        }
        assert_eq!(merged_text(&back, "test"), text);
    }

    #[test]
    fn bad_options_and_names() {
        let none = &|| false;
        for o in [opts(0, 1), opts(4, 1), opts(3, 0)] {
            assert!(merge_sources(&[], o, none).is_err());
        }
        let a: &[u8] = EGG.as_bytes();
        let err = merge_sources(
            &[(Path::new("a"), a), (Path::new("a"), a)],
            opts(3, 1),
            none,
        );
        assert!(err.unwrap_err().to_string().contains("given twice"));
        let bad: &[u8] = b"O\tegg\nX\tno\n";
        let err = merge_sources(
            &[(Path::new("a"), a), (Path::new("b"), bad)],
            opts(3, 1),
            none,
        )
        .unwrap_err();
        assert!(err.to_string().starts_with("b:2:1:"), "{err}");
    }

    #[test]
    fn escaped_paths() {
        let mut s = String::new();
        super::escape("a\\b\tc\nd\re:1", &mut s);
        assert_eq!(s, "a\\\\b\\tc\\nd\\re:1");
        assert_eq!(super::unescape(&s), "a\\b\tc\nd\re:1");
    }
}

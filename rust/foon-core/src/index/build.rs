//! Building a [`Foon`]: objects interned by identity and their written variants, FUs with
//! duplicates dropped, then the producer and consumer lists. Every count and offset is
//! checked against the `u32` columns: the first one that would pass is kept as an
//! [`Error::TooLarge`] and returned by [`Builder::try_finish`] (nothing more is added).

use std::path::Path;

use super::hash::{HashedTable, Table, hash_str, hash_words};
use super::{Csr, DuplicateFu, Foon, NONE, fu_key_into, object_hash};
use crate::error::{Error, Result, Warning};
use crate::model::canonical_into;

/// An object as written in a file, with its string ids in line order (before canonical
/// sorting). `container` is [`NONE`] when there is none.
#[derive(Debug, Clone, Copy)]
pub struct RawObject<'a> {
    pub label: u32,
    pub states: &'a [u32],
    pub ingredients: &'a [u32],
    pub container: u32,
    pub in_motion: u8,
}

// The identity record of an object while building (in `Builder::obj_rec`): its id, its variant
// written in canonical order (or NONE), the first of its other variants (an offset + 1 into
// `Builder::alt_rec`, or 0), label, container, counts of states and ingredients, then the
// canonical states and ingredients. One record holds all that a look-up compares, so that it
// reads one place of memory.
const OBJ_ID: usize = 0;
const OBJ_CANON: usize = 1;
const OBJ_ALT: usize = 2;
const OBJ_HEAD: usize = 7;
// The record of a variant not in canonical order (in `Builder::alt_rec`): its id, the next one
// of its object (offset + 1, or 0), counts, then states and ingredients as written.
const ALT_HEAD: usize = 4;

/// `n` as an offset into a record column (below [`NONE`]).
fn record_offset(n: usize, what: &'static str) -> Result<u32> {
    Error::check_id(n, what)
}

/// Incremental construction of a [`Foon`]; used by the parser (and later by merging).
#[derive(Debug, Default)]
pub struct Builder {
    foon: Foon,
    /// Objects by identity hash (values: offsets of their records in `obj_rec`).
    obj_ix: HashedTable,
    obj_rec: Vec<u32>,
    /// Variants not written in canonical order (see `ALT_HEAD`).
    alt_rec: Vec<u32>,
    /// FUs by identity hash (values: ids), strings by hash (values: ids).
    fu_ix: HashedTable,
    str_ix: HashedTable,
    scratch: Vec<u32>,
    motion_seen: Vec<bool>,
    id_key: Vec<u32>,
    fu_key: Vec<u32>,
    ins: Vec<u32>,
    outs: Vec<u32>,
    in_vars: Vec<u32>,
    out_vars: Vec<u32>,
    /// The source FUs are being read from (set by [`Builder::begin_source`]).
    current: u32,
    /// Further origins of kept FUs: (FU, source, line).
    also: Vec<(u32, u32, u32)>,
    /// The first count that passed what the index holds.
    fail: Option<Error>,
}

impl Builder {
    pub fn new() -> Self {
        let mut b = Self::default();
        for csr in [
            &mut b.foon.obj_states,
            &mut b.foon.obj_ingredients,
            &mut b.foon.var_states,
            &mut b.foon.var_ingredients,
            &mut b.foon.fu_inputs,
            &mut b.foon.fu_outputs,
            &mut b.foon.fu_also,
        ] {
            *csr = Csr::new();
        }
        b
    }

    /// A builder with its tables and columns sized for about `fus` functional units (a hint:
    /// the builder grows past it).
    pub fn with_capacity(fus: usize) -> Self {
        let mut b = Self::new();
        let objects = fus + fus / 2;
        let variants = fus * 2;
        let strings = fus / 2;
        let f = &mut b.foon;
        f.strings.reserve(strings, strings * 16);
        let sized = Table::with_capacity(objects).is_ok() && Table::with_capacity(fus).is_ok();
        if !sized {
            return b;
        }
        b.obj_ix = HashedTable::with_capacity(objects).unwrap_or_default();
        b.fu_ix = HashedTable::with_capacity(fus).unwrap_or_default();
        b.str_ix = HashedTable::with_capacity(strings).unwrap_or_default();
        b.obj_rec.reserve(objects * 9);
        for c in [
            &mut f.obj_label,
            &mut f.obj_container,
            &mut f.obj_first_variant,
            &mut f.obj_hash,
        ] {
            c.make_mut().reserve(objects);
        }
        f.var_obj.make_mut().reserve(variants);
        for c in [
            &mut f.fu_motion,
            &mut f.fu_motion_meta,
            &mut f.fu_line,
            &mut f.fu_source,
            &mut f.fu_hash,
        ] {
            c.make_mut().reserve(fus);
        }
        for c in [&mut f.fu_input_variant, &mut f.fu_output_variant] {
            c.make_mut().reserve(fus * 3);
        }
        for c in [&mut f.fu_input_in_motion, &mut f.fu_output_in_motion] {
            c.make_mut().reserve(fus * 3);
        }
        for (csr, rows, data) in [
            (&mut f.fu_inputs, fus, fus * 3),
            (&mut f.fu_outputs, fus, fus * 3),
            (&mut f.obj_states, objects, objects),
            (&mut f.obj_ingredients, objects, objects),
            (&mut f.var_states, variants, variants),
            (&mut f.var_ingredients, variants, variants),
        ] {
            csr.off.make_mut().reserve(rows + 1);
            csr.data.make_mut().reserve(data);
        }
        b
    }

    /// A builder for a source of `bytes` bytes of FOON text (about 250 bytes per unit).
    pub fn for_bytes(bytes: usize) -> Self {
        Self::with_capacity(bytes / 250)
    }

    /// The first size error met, if any (see [`Builder::try_finish`]).
    pub fn error(&self) -> Option<&Error> {
        self.fail.as_ref()
    }

    fn failed(&mut self, e: Error) {
        if self.fail.is_none() {
            self.fail = Some(e);
        }
    }

    /// Starts a new source (a file, or text given in memory when `path` is `None`): the FUs
    /// added from now on come from it. Returns its id.
    pub fn begin_source(&mut self, path: Option<&Path>) -> u32 {
        let id = match Error::check_id(self.foon.sources.len(), "sources") {
            Ok(id) => id,
            Err(e) => {
                self.failed(e);
                return self.current;
            }
        };
        let name = path.map(|p| p.to_string_lossy()).unwrap_or_default();
        self.foon.sources.push(&name);
        self.current = id;
        id
    }

    /// Records that FU `fu` was also found in `source` at `line` (merging).
    pub fn add_origin(&mut self, fu: u32, source: u32, line: u32) {
        self.also.push((fu, source, line));
    }

    /// The id of string `s`, added when new (0 once a size error is met, see
    /// [`Builder::error`]).
    pub fn intern(&mut self, s: &str) -> u32 {
        self.intern_hashed(s, hash_str(s))
    }

    /// As [`Builder::intern`], given `h == hash_str(s)` (computed beforehand, for example
    /// on another thread).
    pub(crate) fn intern_hashed(&mut self, s: &str, h: u32) -> u32 {
        let strings = &self.foon.strings;
        if let Some(id) = self.str_ix.find(h, |id| strings.text(id) == s) {
            return id;
        }
        match self
            .foon
            .strings
            .push_new(s, h)
            .and_then(|id| self.str_ix.insert(h, id).map(|()| id))
        {
            Ok(id) => id,
            Err(e) => {
                self.failed(e);
                0
            }
        }
    }

    pub fn text(&self, id: u32) -> &str {
        self.foon.strings.text(id)
    }

    pub fn fu_count(&self) -> usize {
        self.foon.fu_count()
    }

    /// Interns an object occurrence; returns `(object id, variant id)`.
    fn object(&mut self, raw: &RawObject<'_>) -> Result<(u32, u32)> {
        // Canonical form: states then ingredients, each sorted by id, in one scratch buffer.
        let key = &mut self.id_key;
        let ns = canonical_into(raw.states, raw.ingredients, key);
        let (states, ingredients) = key.split_at(ns);
        let h = object_hash(raw.label, raw.container, states, ingredients);
        let rec = &self.obj_rec;
        let head = [
            raw.label,
            raw.container,
            ns as u32,
            ingredients.len() as u32,
        ];
        let found = self.obj_ix.find(h, |at| {
            let r = &rec[at as usize..];
            r[3..OBJ_HEAD] == head && r[OBJ_HEAD..OBJ_HEAD + key.len()] == key[..]
        });
        let f = &mut self.foon;
        let at = if let Some(at) = found {
            at as usize
        } else {
            let o = Error::check_id(f.obj_label.len(), "objects")?;
            let at = record_offset(self.obj_rec.len(), "object records")?;
            f.obj_states.try_push_row(states, "object states")?;
            f.obj_ingredients
                .try_push_row(ingredients, "object ingredients")?;
            f.obj_label.push(raw.label);
            f.obj_container.push(raw.container);
            f.obj_first_variant.push(NONE);
            f.obj_hash.push(h);
            self.obj_rec.extend_from_slice(&[o, NONE, 0]);
            self.obj_rec.extend_from_slice(&head);
            self.obj_rec.extend_from_slice(key);
            self.obj_ix.insert(h, at)?;
            at as usize
        };
        let obj = self.obj_rec[at + OBJ_ID];
        let canonical = raw.states == states && raw.ingredients == ingredients;
        let var = if canonical {
            let v = self.obj_rec[at + OBJ_CANON];
            if v == NONE {
                let v = self.new_variant(obj, raw)?;
                self.obj_rec[at + OBJ_CANON] = v;
                v
            } else {
                v
            }
        } else {
            let counts = [raw.states.len() as u32, raw.ingredients.len() as u32];
            let mut link = self.obj_rec[at + OBJ_ALT];
            // Where the link to a new variant goes: the object's record, or the last variant's.
            let mut last = None;
            let mut found = None;
            while link != 0 {
                let r = &self.alt_rec[link as usize - 1..];
                let (ws, rest) = r[ALT_HEAD..].split_at(counts[0] as usize);
                if r[2..ALT_HEAD] == counts
                    && ws == raw.states
                    && &rest[..counts[1] as usize] == raw.ingredients
                {
                    found = Some(r[0]);
                    break;
                }
                last = Some(link as usize); // the `next` field of this record, in `alt_rec`
                link = r[1];
            }
            if let Some(v) = found {
                v
            } else {
                let v = self.new_variant(obj, raw)?;
                let off = record_offset(self.alt_rec.len() + 1, "variant records")?;
                self.alt_rec.extend_from_slice(&[v, 0]);
                self.alt_rec.extend_from_slice(&counts);
                self.alt_rec.extend_from_slice(raw.states);
                self.alt_rec.extend_from_slice(raw.ingredients);
                match last {
                    None => self.obj_rec[at + OBJ_ALT] = off,
                    Some(l) => self.alt_rec[l] = off,
                }
                v
            }
        };
        if found.is_none() {
            // A new object: this is its first variant.
            self.foon.obj_first_variant[obj as usize] = var;
        }
        Ok((obj, var))
    }

    /// Adds a variant of object `obj` as `raw` writes it; returns its id.
    fn new_variant(&mut self, obj: u32, raw: &RawObject<'_>) -> Result<u32> {
        let f = &mut self.foon;
        let v = Error::check_id(f.var_obj.len(), "object variants")?;
        f.var_states.try_push_row(raw.states, "variant states")?;
        f.var_ingredients
            .try_push_row(raw.ingredients, "variant ingredients")?;
        f.var_obj.push(obj);
        Ok(v)
    }

    /// Adds an FU; returns its index, or the index of the earlier equal FU when it is a
    /// duplicate (`Err`), in which case it is recorded and dropped. Once a size error is met
    /// (see [`Builder::error`]) nothing is added and the answer is `Err(NONE)`.
    pub fn add_fu(
        &mut self,
        motion: u32,
        motion_meta: u32,
        inputs: &[RawObject<'_>],
        outputs: &[RawObject<'_>],
        line: u32,
    ) -> Result<u32, u32> {
        if self.fail.is_some() {
            return Err(NONE);
        }
        match self.try_add_fu(motion, motion_meta, inputs, outputs, line) {
            Ok(r) => r,
            Err(e) => {
                self.failed(e);
                Err(NONE)
            }
        }
    }

    fn try_add_fu(
        &mut self,
        motion: u32,
        motion_meta: u32,
        inputs: &[RawObject<'_>],
        outputs: &[RawObject<'_>],
        line: u32,
    ) -> Result<Result<u32, u32>> {
        let mut in_ids = std::mem::take(&mut self.ins);
        let mut out_ids = std::mem::take(&mut self.outs);
        let mut in_vars = std::mem::take(&mut self.in_vars);
        let mut out_vars = std::mem::take(&mut self.out_vars);
        let mut key = std::mem::take(&mut self.fu_key);
        for v in [
            &mut in_ids,
            &mut out_ids,
            &mut in_vars,
            &mut out_vars,
            &mut key,
        ] {
            v.clear();
        }
        let result = self.add_fu_with(
            motion,
            motion_meta,
            inputs,
            outputs,
            line,
            [&mut in_ids, &mut out_ids, &mut in_vars, &mut out_vars],
            &mut key,
        );
        self.ins = in_ids;
        self.outs = out_ids;
        self.in_vars = in_vars;
        self.out_vars = out_vars;
        self.fu_key = key;
        result
    }

    #[allow(clippy::too_many_arguments)]
    fn add_fu_with(
        &mut self,
        motion: u32,
        motion_meta: u32,
        inputs: &[RawObject<'_>],
        outputs: &[RawObject<'_>],
        line: u32,
        [in_ids, out_ids, in_vars, out_vars]: [&mut Vec<u32>; 4],
        key: &mut Vec<u32>,
    ) -> Result<Result<u32, u32>> {
        for raw in inputs {
            let (o, v) = self.object(raw)?;
            in_ids.push(o);
            in_vars.push(v);
        }
        for raw in outputs {
            let (o, v) = self.object(raw)?;
            out_ids.push(o);
            out_vars.push(v);
        }
        fu_key_into(motion, in_ids, out_ids, key);
        let h = hash_words(key);
        let (f, scratch) = (&self.foon, &mut self.scratch);
        let found = self.fu_ix.find(h, |g| {
            fu_key_into(f.fu_motion[g as usize], f.inputs(g), f.outputs(g), scratch);
            scratch == key
        });
        if let Some(first) = found {
            let source = self.current;
            self.foon.report.duplicates.push(DuplicateFu {
                line,
                of: first,
                source,
            });
            self.also.push((first, source, line));
            return Ok(Err(first));
        }
        let f = &mut self.foon;
        let idx = Error::check_id(f.fu_motion.len(), "functional units")?;
        Error::check_offset(f.fu_inputs.data().len() + in_ids.len(), "input edges")?;
        Error::check_offset(f.fu_outputs.data().len() + out_ids.len(), "output edges")?;
        f.fu_inputs.try_push_row(in_ids, "input edges")?;
        f.fu_outputs.try_push_row(out_ids, "output edges")?;
        f.fu_motion.push(motion);
        f.fu_motion_meta.push(motion_meta);
        f.fu_line.push(line);
        f.fu_source.push(self.current);
        f.fu_input_variant.extend_from_slice(in_vars);
        f.fu_output_variant.extend_from_slice(out_vars);
        f.fu_input_in_motion
            .extend(inputs.iter().map(|r| r.in_motion));
        f.fu_output_in_motion
            .extend(outputs.iter().map(|r| r.in_motion));
        f.fu_hash.push(h);
        self.fu_ix.insert(h, idx)?;
        let m = motion as usize;
        if self.motion_seen.len() <= m {
            self.motion_seen.resize(m + 1, false);
        }
        if !self.motion_seen[m] {
            self.motion_seen[m] = true;
            f.motions.push(motion);
        }
        Ok(Ok(idx))
    }

    pub fn warn(&mut self, w: Warning) {
        self.foon.report.warnings.push(w);
    }

    pub fn note(&mut self, w: Warning) {
        self.foon.report.notes.push(w);
    }

    /// Finishes the index: builds producers (course rule), consumers and the provenance
    /// rows, and lays the identity tables out at their canonical size. A size error met while
    /// building is returned here.
    pub fn try_finish(self) -> Result<Foon> {
        if let Some(e) = self.fail {
            return Err(e);
        }
        // The look-up tables of the build are done with: free them before the lists are built.
        drop((
            self.obj_ix,
            self.obj_rec,
            self.alt_rec,
            self.fu_ix,
            self.str_ix,
        ));
        let mut f = self.foon;
        if f.sources.len() == 0 {
            f.sources.push("");
        }
        let n_fu = f.fu_motion.len();
        let mut rest = self.also;
        rest.sort_by_key(|&(fu, _, _)| fu); // stable: each row keeps the reading order
        let mut also = Csr::with_capacity(n_fu, rest.len() * 2);
        let mut pairs = Vec::new();
        let mut it = rest.into_iter().peekable();
        for fu in 0..n_fu as u32 {
            pairs.clear();
            while let Some(&(_, s, l)) = it.peek().filter(|&&(g, _, _)| g == fu) {
                pairs.extend([s, l]);
                it.next();
            }
            also.try_push_row(&pairs, "provenance entries")?;
        }
        f.fu_also = also;
        let n_obj = f.obj_label.len();
        let outs = &f.fu_outputs;
        let bare: Vec<bool> = (0..n_obj as u32)
            .map(|o| {
                f.obj_states.row(o).is_empty()
                    && f.obj_ingredients.row(o).is_empty()
                    && f.obj_container[o as usize] == NONE
            })
            .collect();
        // An FU that outputs the same object twice is listed once as its producer.
        let prod_pairs = (0..n_fu as u32).flat_map(|fu| {
            let row = outs.row(fu);
            row.iter()
                .enumerate()
                .filter(|&(k, &o)| !bare[o as usize] && !row[..k].contains(&o))
                .map(move |(_, &o)| (o, fu))
        });
        let ins = &f.fu_inputs;
        let cons_pairs = (0..n_fu as u32).flat_map(|fu| ins.row(fu).iter().map(move |&o| (o, fu)));
        // The lists and the tables are independent: built side by side on the thread pool.
        let (obj_hash, fu_hash) = (&f.obj_hash, &f.fu_hash);
        let ((producers, consumers), (obj_table, fu_table)) =
            crate::search::batch::in_pool(|| {
                rayon::join(
                    || {
                        rayon::join(
                            || Csr::try_from_pairs(n_obj, prod_pairs, "producer entries"),
                            || Csr::try_from_pairs(n_obj, cons_pairs, "input edges"),
                        )
                    },
                    || {
                        rayon::join(
                            || Table::rebuild(obj_hash, 0),
                            || Table::rebuild(fu_hash, 0),
                        )
                    },
                )
            })?;
        f.producers = producers?;
        f.consumers = consumers?;
        f.strings.finish()?;
        f.obj_table = obj_table?;
        f.fu_table = fu_table?;
        for c in [
            &mut f.obj_label,
            &mut f.obj_container,
            &mut f.obj_first_variant,
            &mut f.obj_hash,
            &mut f.var_obj,
            &mut f.fu_motion,
            &mut f.fu_motion_meta,
            &mut f.fu_line,
            &mut f.fu_input_variant,
            &mut f.fu_output_variant,
            &mut f.motions,
            &mut f.fu_hash,
            &mut f.fu_source,
        ] {
            c.shrink_to_fit();
        }
        f.fu_input_in_motion.shrink_to_fit();
        f.sources.text.shrink_to_fit();
        f.sources.ends.shrink_to_fit();
        f.fu_output_in_motion.shrink_to_fit();
        for c in [
            &mut f.obj_states,
            &mut f.obj_ingredients,
            &mut f.var_states,
            &mut f.var_ingredients,
            &mut f.fu_inputs,
            &mut f.fu_outputs,
        ] {
            c.shrink_to_fit();
        }
        Ok(f)
    }

    /// As [`Builder::try_finish`], for callers that cannot meet a size error: past the
    /// limits of the columns (4294967295 objects, input edges, ...), the index built so far,
    /// with no units.
    pub fn finish(self) -> Foon {
        self.try_finish().unwrap_or_else(|_| {
            let mut b = Builder::new();
            b.begin_source(None);
            b.try_finish().unwrap_or_default()
        })
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::Builder;
    use crate::parse::{ParseOptions, parse_into};

    const A: &str = "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n";
    const B: &str = "O\tbread\nS\twhole\nM\tslice\nO\tbread\nS\tsliced\n//\n";

    /// Several sources build one index; an FU found again keeps its first copy and records
    /// every (source, line) it was found at; support counts distinct sources.
    #[test]
    fn sources_and_origins() {
        let mut b = Builder::new();
        let none = &|| false;
        let opts = ParseOptions::default();
        let aa = format!("{A}{A}");
        parse_into(
            &mut b,
            aa.as_bytes(),
            Some(Path::new("a.txt")),
            opts,
            None,
            none,
        )
        .unwrap();
        let ba = format!("{B}{A}");
        parse_into(
            &mut b,
            ba.as_bytes(),
            Some(Path::new("b.txt")),
            opts,
            None,
            none,
        )
        .unwrap();
        let f = b.finish();
        assert_eq!(f.fu_count(), 2);
        assert_eq!(f.source_count(), 2);
        assert_eq!((f.source_name(0), f.source_name(1)), ("a.txt", "b.txt"));
        assert_eq!(f.origins(0).collect::<Vec<_>>(), [(0, 1), (0, 7), (1, 7)]);
        assert_eq!(f.origins(1).collect::<Vec<_>>(), [(1, 1)]);
        assert_eq!((f.support(0), f.support(1)), (2, 1));
        assert_eq!(f.fu_source(1), 1);
        assert_eq!(f.duplicates().len(), 2);
        assert_eq!(f.source(), Some(Path::new("a.txt")));
    }
}

//! The compact, immutable index of a FOON: interned strings, an object table keyed by
//! identity, and CSR arrays (flat offset + data columns of `u32`) for FU inputs, FU outputs,
//! producers and consumers, with flat identity tables (see [`hash`]). Every column is a
//! [`Col`]: a plain run of little-endian integers, owned or borrowed from a memory-mapped
//! `.foonidx` file ([`file`](mod@file)), so the layout is position independent and the same search
//! code runs on both. This module holds the [`Foon`] and its look-ups; [`Builder`] makes one.

mod build;
mod col;
mod csr;
pub mod file;
pub mod hash;
mod interner;

use std::path::Path;
use std::sync::{Arc, OnceLock};

use rustc_hash::FxHashSet;

use crate::error::{Error, Result, Warning};
use crate::model::{ObjectSpec, canonical_into};

pub use build::{Builder, RawObject};
pub use col::Col;
pub use csr::Csr;
pub(crate) use csr::Rows;
pub use hash::Table;
pub use interner::Interner;

use hash::{WordHasher, hash_words};
use interner::StrList;

/// "No value" in a `u32` column (no container, no metadata).
pub const NONE: u32 = u32::MAX;

/// An FU dropped because it repeats an earlier one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DuplicateFu {
    /// Line where the dropped copy starts.
    pub line: u32,
    /// Index of the kept copy.
    pub of: u32,
    /// Source (see [`Foon::source_name`]) of the dropped copy.
    pub source: u32,
}

/// What loading found besides the index: warnings, lint notes and the duplicates dropped.
/// It is not part of the index (an index file does not carry it).
#[derive(Debug, Clone, Default)]
pub struct Report {
    pub warnings: Vec<Warning>,
    /// Lint notes found while parsing (not warnings: strict mode ignores them).
    pub notes: Vec<Warning>,
    /// Dropped copies, in the order they were read.
    pub duplicates: Vec<DuplicateFu>,
}

/// The objects of each label, in id order: a counting sort of the objects by label string
/// id (`start[l]..start[l + 1]` of `objects`).
#[derive(Debug, Clone, Default)]
pub(crate) struct ByLabel {
    start: Vec<u32>,
    objects: Vec<u32>,
}

impl ByLabel {
    fn build(foon: &Foon) -> Self {
        let n = foon.strings.len();
        let mut start = vec![0u32; n + 2];
        for o in 0..foon.object_count() {
            let l = foon.obj_label.get(o).copied().unwrap_or(u32::MAX) as usize;
            if l < n {
                start[l + 2] += 1;
            }
        }
        for l in 2..start.len() {
            start[l] += start[l - 1];
        }
        let mut objects = vec![0u32; start[n + 1] as usize];
        for o in 0..foon.object_count() {
            let l = foon.obj_label.get(o).copied().unwrap_or(u32::MAX) as usize;
            if l < n {
                let at = &mut start[l + 1];
                objects[*at as usize] = o as u32;
                *at += 1;
            }
        }
        start.truncate(n + 1);
        Self { start, objects }
    }

    fn objects(&self, label: u32) -> &[u32] {
        let l = label as usize;
        match (self.start.get(l), self.start.get(l + 1)) {
            (Some(&a), Some(&b)) => &self.objects[a as usize..b as usize],
            _ => &[],
        }
    }
}

/// A parsed FOON: immutable once built, `Send + Sync`, shared behind `Arc`.
#[derive(Debug, Clone, Default)]
pub struct Foon {
    pub(crate) strings: Interner,
    // Objects, by id: canonical identity (states and ingredients sorted by string id).
    pub(crate) obj_label: Col<u32>,
    pub(crate) obj_container: Col<u32>,
    pub(crate) obj_states: Csr,
    pub(crate) obj_ingredients: Csr,
    pub(crate) obj_first_variant: Col<u32>,
    /// Identity hash of each object (see [`object_hash`]) and the table that finds them.
    pub(crate) obj_hash: Col<u32>,
    pub(crate) obj_table: Table,
    // Variants: an object as written somewhere (its own state and ingredient order).
    pub(crate) var_obj: Col<u32>,
    pub(crate) var_states: Csr,
    pub(crate) var_ingredients: Csr,
    // FUs, by index (file order after dropping faulty and duplicate FUs).
    pub(crate) fu_motion: Col<u32>,
    pub(crate) fu_motion_meta: Col<u32>,
    pub(crate) fu_line: Col<u32>,
    pub(crate) fu_inputs: Csr,
    pub(crate) fu_outputs: Csr,
    pub(crate) fu_input_variant: Col<u32>,
    pub(crate) fu_output_variant: Col<u32>,
    pub(crate) fu_input_in_motion: Col<u8>,
    pub(crate) fu_output_in_motion: Col<u8>,
    // Adjacency.
    pub(crate) producers: Csr,
    pub(crate) consumers: Csr,
    pub(crate) motions: Col<u32>,
    /// Identity hash of each FU (of its key, see [`fu_key_into`]) and the table that finds them.
    pub(crate) fu_hash: Col<u32>,
    pub(crate) fu_table: Table,
    // Provenance: the sources read (paths, or "" for text given in memory), the source of
    // each FU's kept copy (its line is `fu_line`), and every other (source, line) where the
    // same FU was found, as pairs in one row per FU.
    pub(crate) sources: StrList,
    pub(crate) fu_source: Col<u32>,
    pub(crate) fu_also: Csr,
    /// The load report (not part of the index).
    pub(crate) report: Report,
    /// Labels that some object has with the state `empty` (computed on first use).
    pub(crate) empty_labels: OnceLock<FxHashSet<u32>>,
    /// The content fingerprint (read from the header of an index file, else computed on
    /// first use).
    pub(crate) fingerprint: OnceLock<[u8; 16]>,
    /// The similarity index of `foon find` and of the goals a "not found" error suggests
    /// (built on first use).
    pub(crate) find: OnceLock<crate::find::FindIndex>,
    /// The objects of each label (built on first use, see [`Foon::objects_with_label`]).
    pub(crate) by_label: OnceLock<ByLabel>,
    /// The index file this FOON was opened from, if any.
    pub(crate) file: Option<Arc<file::Opened>>,
}

/// Counts shown by `foon stats`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    pub functional_units: usize,
    pub objects: usize,
    pub produced_objects: usize,
    pub motions: usize,
    pub strings: usize,
    pub input_edges: usize,
    pub output_edges: usize,
    pub duplicates_dropped: usize,
    pub warnings: usize,
    pub index_bytes: usize,
}

impl Foon {
    pub fn fu_count(&self) -> usize {
        self.fu_motion.len()
    }

    pub fn object_count(&self) -> usize {
        self.obj_label.len()
    }

    pub fn strings(&self) -> &Interner {
        &self.strings
    }

    pub fn text(&self, id: u32) -> &str {
        self.strings.text(id)
    }

    /// The file the FOON was read from: its first source, when that was a file.
    pub fn source(&self) -> Option<&Path> {
        Some(self.sources.get(0))
            .filter(|s| !s.is_empty())
            .map(Path::new)
    }

    /// Number of sources the index was built from.
    pub fn source_count(&self) -> usize {
        self.sources.len()
    }

    /// The path of source `id` as given when it was read (`""` for text given in memory).
    pub fn source_name(&self, id: u32) -> &str {
        self.sources.get(id as usize)
    }

    /// Source of FU `fu`'s kept copy (its line is [`Foon::fu_line`]).
    pub fn fu_source(&self, fu: u32) -> u32 {
        self.fu_source.get(fu as usize).copied().unwrap_or(NONE)
    }

    /// Every (source, line) where FU `fu` was found: its kept copy first, then the dropped
    /// copies in the order they were read.
    pub fn origins(&self, fu: u32) -> impl Iterator<Item = (u32, u32)> + '_ {
        let also = self.fu_also.row(fu);
        std::iter::once((self.fu_source(fu), self.fu_line(fu)))
            .chain(also.chunks_exact(2).map(|p| (p[0], p[1])))
    }

    /// Support of FU `fu`: the number of distinct sources that contain it.
    pub fn support(&self, fu: u32) -> usize {
        let own = self.fu_source(fu);
        let also = self.fu_also.row(fu);
        let mut others: Vec<u32> = also
            .chunks_exact(2)
            .map(|p| p[0])
            .filter(|&s| s != own)
            .collect();
        others.sort_unstable();
        others.dedup();
        1 + others.len()
    }

    /// The load report: warnings, notes and dropped duplicates.
    pub fn report(&self) -> &Report {
        &self.report
    }

    /// Replaces the load report (a FOON rebuilt from its index bytes gets its report back).
    pub fn set_report(&mut self, report: Report) {
        self.report = report;
    }

    /// The index file this FOON was opened from ([`Foon::open_index`]), if any.
    pub fn index_path(&self) -> Option<&Path> {
        self.file.as_ref().and_then(|f| f.path.as_deref())
    }

    /// The content fingerprint: XXH3-128 over every content column of the index (strings,
    /// objects, variants, FUs, adjacency, sources and provenance; not the identity tables,
    /// which follow from them, and not the load report). Equal for the same content whether
    /// the index was built from text or opened from a file, where it is read from the header.
    pub fn fingerprint(&self) -> [u8; 16] {
        *self.fingerprint.get_or_init(|| file::fingerprint_of(self))
    }

    /// The fingerprint as 32 lowercase hexadecimal digits.
    pub fn fingerprint_hex(&self) -> String {
        use std::fmt::Write as _;
        self.fingerprint()
            .iter()
            .fold(String::with_capacity(32), |mut s, b| {
                let _ = write!(s, "{b:02x}");
                s
            })
    }

    pub fn warnings(&self) -> &[Warning] {
        &self.report.warnings
    }

    /// Lint notes found while parsing (spaced or repeated ingredients, empty containers).
    pub fn notes(&self) -> &[Warning] {
        &self.report.notes
    }

    pub fn duplicates(&self) -> &[DuplicateFu] {
        &self.report.duplicates
    }

    #[inline]
    pub fn inputs(&self, fu: u32) -> &[u32] {
        self.fu_inputs.row(fu)
    }

    #[inline]
    pub fn outputs(&self, fu: u32) -> &[u32] {
        self.fu_outputs.row(fu)
    }

    /// FUs that produce `obj`, in file order (course indexing rule applied).
    #[inline]
    pub fn producers(&self, obj: u32) -> &[u32] {
        self.producers.row(obj)
    }

    /// FUs that take `obj` as an input, in file order (one entry per input slot).
    #[inline]
    pub fn consumers(&self, obj: u32) -> &[u32] {
        self.consumers.row(obj)
    }

    #[inline]
    pub fn motion(&self, fu: u32) -> u32 {
        self.fu_motion[fu as usize]
    }

    pub fn motion_text(&self, fu: u32) -> &str {
        self.text(self.fu_motion.get(fu as usize).copied().unwrap_or(NONE))
    }

    /// Extra fields of the motion line (times), if any.
    pub fn motion_meta(&self, fu: u32) -> Option<&str> {
        match self.fu_motion_meta.get(fu as usize) {
            Some(&m) if m != NONE => Some(self.text(m)),
            _ => None,
        }
    }

    /// Line of the source file where FU `fu` starts.
    pub fn fu_line(&self, fu: u32) -> u32 {
        self.fu_line.get(fu as usize).copied().unwrap_or(0)
    }

    /// Distinct motion string ids, in first-seen order.
    pub fn motion_ids(&self) -> &[u32] {
        &self.motions
    }

    #[inline]
    pub fn label(&self, obj: u32) -> u32 {
        self.obj_label[obj as usize]
    }

    pub fn label_text(&self, obj: u32) -> &str {
        self.text(self.obj_label.get(obj as usize).copied().unwrap_or(NONE))
    }

    #[inline]
    pub fn container(&self, obj: u32) -> u32 {
        self.obj_container[obj as usize]
    }

    /// Canonical states of `obj` (a multiset, sorted by string id).
    pub fn states(&self, obj: u32) -> &[u32] {
        self.obj_states.row(obj)
    }

    /// Canonical ingredients of `obj` (a multiset, sorted by string id).
    #[inline]
    pub fn ingredients(&self, obj: u32) -> &[u32] {
        self.obj_ingredients.row(obj)
    }

    /// True when the object has no state, no ingredient and no container (`knife`): such an
    /// output is not indexed as produced (course rule).
    pub fn is_bare(&self, obj: u32) -> bool {
        self.states(obj).is_empty()
            && self.ingredients(obj).is_empty()
            && self.container(obj) == NONE
    }

    /// The variant (written form) in which `obj` was first seen.
    pub fn first_variant(&self, obj: u32) -> u32 {
        self.obj_first_variant[obj as usize]
    }

    pub fn input_variants(&self, fu: u32) -> &[u32] {
        let s = self.fu_inputs.row_start(fu);
        &self.fu_input_variant[s..s + self.inputs(fu).len()]
    }

    pub fn output_variants(&self, fu: u32) -> &[u32] {
        let s = self.fu_outputs.row_start(fu);
        &self.fu_output_variant[s..s + self.outputs(fu).len()]
    }

    /// Object-in-motion flags of the inputs of `fu` (0, 1, or 2 when not given).
    pub fn input_in_motion(&self, fu: u32) -> &[u8] {
        let s = self.fu_inputs.row_start(fu);
        &self.fu_input_in_motion[s..s + self.inputs(fu).len()]
    }

    /// Object-in-motion flags of the outputs of `fu` (0, 1, or 2 when not given).
    pub fn output_in_motion(&self, fu: u32) -> &[u8] {
        let s = self.fu_outputs.row_start(fu);
        &self.fu_output_in_motion[s..s + self.outputs(fu).len()]
    }

    pub fn variant_object(&self, var: u32) -> u32 {
        self.var_obj[var as usize]
    }

    /// States of a variant, in its own line order.
    pub fn variant_states(&self, var: u32) -> &[u32] {
        self.var_states.row(var)
    }

    /// Ingredients of a variant, in its own order.
    pub fn variant_ingredients(&self, var: u32) -> &[u32] {
        self.var_ingredients.row(var)
    }

    /// The object with this identity (string ids, any order), if there is one.
    pub fn find_object_ids(
        &self,
        label: u32,
        states: &[u32],
        ingredients: &[u32],
        container: u32,
    ) -> Option<u32> {
        let mut key = Vec::with_capacity(states.len() + ingredients.len());
        let ns = canonical_into(states, ingredients, &mut key);
        let (st, ing) = key.split_at(ns);
        self.find_sorted(label, st, ing, container)
    }

    /// As [`Foon::find_object_ids`], with states and ingredients already sorted by id.
    pub(crate) fn find_sorted(
        &self,
        label: u32,
        states: &[u32],
        ingredients: &[u32],
        container: u32,
    ) -> Option<u32> {
        let h = object_hash(label, container, states, ingredients);
        self.obj_table.find(h, &self.obj_hash, |o| {
            self.same_object(o, label, states, ingredients, container)
        })
    }

    fn same_object(
        &self,
        o: u32,
        label: u32,
        states: &[u32],
        ingredients: &[u32],
        container: u32,
    ) -> bool {
        self.obj_label.get(o as usize) == Some(&label)
            && self.obj_container.get(o as usize) == Some(&container)
            && self.obj_states.row(o) == states
            && self.obj_ingredients.row(o) == ingredients
    }

    /// The object with this identity given as text, if there is one.
    pub fn find_object(
        &self,
        label: &str,
        states: &[&str],
        ingredients: &[&str],
        container: Option<&str>,
    ) -> Option<u32> {
        let l = self.strings.get(label)?;
        let c = match container {
            Some(c) => self.strings.get(c)?,
            None => NONE,
        };
        let s: Option<Vec<u32>> = states.iter().map(|s| self.strings.get(s)).collect();
        let i: Option<Vec<u32>> = ingredients.iter().map(|s| self.strings.get(s)).collect();
        self.find_object_ids(l, &s?, &i?, c)
    }

    /// The similarity index over this FOON's objects ([`FindIndex`](crate::find::FindIndex)),
    /// built once, on first use.
    pub fn find_index(&self) -> &crate::find::FindIndex {
        self.find
            .get_or_init(|| crate::find::FindIndex::build(self))
    }

    /// The labels (string ids) that some object has with the state `empty`: the FOON's
    /// vessels, which the step wording names as `the bowl of ...`. Computed once per FOON.
    pub(crate) fn empty_labels(&self) -> &FxHashSet<u32> {
        self.empty_labels.get_or_init(|| {
            let Some(empty) = self.strings.get("empty") else {
                return FxHashSet::default();
            };
            (0..self.object_count() as u32)
                .filter(|&o| self.states(o).contains(&empty))
                .map(|o| self.label(o))
                .collect()
        })
    }

    /// Objects whose label is `label`, in id order.
    /// The first call builds a table of every label's objects (O(objects + strings), once
    /// per FOON); each call after that costs the label's look-up and its objects.
    pub fn objects_with_label(&self, label: &str) -> Vec<u32> {
        let Some(l) = self.strings.get(label) else {
            return Vec::new();
        };
        self.by_label
            .get_or_init(|| ByLabel::build(self))
            .objects(l)
            .to_vec()
    }

    /// The FU with this identity (motion string id, and inputs and outputs as object ids
    /// in any order: multisets), if there is one. The identity is the one that drops
    /// duplicate FUs on load.
    pub fn find_fu(&self, motion: u32, inputs: &[u32], outputs: &[u32]) -> Option<u32> {
        let mut key = Vec::new();
        fu_key_into(motion, inputs, outputs, &mut key);
        self.find_fu_key(&key, hash_words(&key), &mut Vec::new())
    }

    /// The FU whose identity key ([`fu_key_into`]) is `key`, hashed `h`.
    pub(crate) fn find_fu_key(&self, key: &[u32], h: u32, scratch: &mut Vec<u32>) -> Option<u32> {
        self.fu_table.find(h, &self.fu_hash, |g| {
            fu_key_into(
                self.fu_motion.get(g as usize).copied().unwrap_or(NONE),
                self.inputs(g),
                self.outputs(g),
                scratch,
            );
            *scratch == key
        })
    }

    /// The goal object for a spec: the object with its identity, or
    /// [`Error::GoalNotFound`] ("The goal node does not exist: ...", with the nearest
    /// objects).
    pub fn goal_by_spec(&self, spec: &ObjectSpec) -> Result<u32> {
        spec.find_in(self).ok_or_else(|| {
            crate::find::goal_not_found(
                self,
                spec.describe(),
                &spec.label,
                &spec.states,
                spec.container.as_deref(),
            )
        })
    }

    /// The goal object for a label that exactly one object has; [`Error::GoalNotFound`]
    /// when none has it, [`Error::GoalAmbiguous`] (one line, at most five objects shown)
    /// when several have it.
    pub fn goal_by_label(&self, label: &str) -> Result<u32> {
        const SHOWN: usize = 5;
        let ids = self.objects_with_label(label);
        match ids.as_slice() {
            [] => Err(crate::find::goal_not_found(
                self,
                label.to_owned(),
                label,
                &[],
                None,
            )),
            [one] => Ok(*one),
            many => Err(Error::GoalAmbiguous {
                label: label.to_owned(),
                count: many.len(),
                shown: many
                    .iter()
                    .take(SHOWN)
                    .map(|&o| ObjectSpec::of_object(self, o).describe())
                    .collect(),
            }),
        }
    }

    /// The goal object for an object id: `id` itself when it is an object of this FOON,
    /// else [`Error::GoalNotFound`].
    pub fn goal_by_id(&self, id: u32) -> Result<u32> {
        if (id as usize) < self.object_count() {
            Ok(id)
        } else {
            Err(Error::GoalNotFound {
                goal: format!(
                    "object id {id} (the FOON has {} objects)",
                    self.object_count()
                ),
                nearest: Vec::new(),
            })
        }
    }

    pub fn stats(&self) -> Stats {
        let produced = (0..self.object_count() as u32)
            .filter(|&o| !self.producers(o).is_empty())
            .count();
        let index_bytes = self.columns().iter().map(file::ColRef::heap_bytes).sum();
        Stats {
            functional_units: self.fu_count(),
            objects: self.object_count(),
            produced_objects: produced,
            motions: self.motions.len(),
            strings: self.strings.len(),
            input_edges: self.fu_inputs.data().len(),
            output_edges: self.fu_outputs.data().len(),
            duplicates_dropped: self.report.duplicates.len(),
            warnings: self.report.warnings.len(),
            index_bytes,
        }
    }
}

/// Identity hash of an object: [`hash_words`] of `[label, container, number of states,
/// states..., ingredients...]`, states and ingredients each sorted by id.
pub(crate) fn object_hash(label: u32, container: u32, states: &[u32], ingredients: &[u32]) -> u32 {
    let mut h = WordHasher::new();
    h.word(label);
    h.word(container);
    h.word(states.len() as u32);
    h.words(states);
    h.words(ingredients);
    h.finish()
}

/// The identity key of an FU: its motion, the number of inputs, the inputs sorted, the
/// outputs sorted (SEMANTICS §2: same motion, same multisets of inputs and of outputs).
pub(super) fn fu_key_into(motion: u32, inputs: &[u32], outputs: &[u32], key: &mut Vec<u32>) {
    key.clear();
    key.push(motion);
    key.push(inputs.len() as u32);
    key.extend_from_slice(inputs);
    key[2..].sort_unstable();
    let s = key.len();
    key.extend_from_slice(outputs);
    key[s..].sort_unstable();
}

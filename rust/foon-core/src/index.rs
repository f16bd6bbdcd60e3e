//! The compact, immutable index of a FOON: interned strings, an object table keyed by
//! identity, and CSR arrays (flat offset + data vectors of `u32`) for FU inputs, FU outputs,
//! producers and consumers. Every array is a plain vector of integers, so the layout is
//! position independent and can later be written to disk and memory-mapped as it is.

use std::path::PathBuf;

use std::hash::Hasher;

use hashbrown::HashTable;
use rustc_hash::FxHasher;

use crate::error::{Error, Result, Warning};
use crate::model::{ObjectSpec, canonical_into};

/// "No value" in a `u32` column (no container, no metadata).
pub const NONE: u32 = u32::MAX;

/// Compressed sparse rows: row `i` is `data[off[i]..off[i + 1]]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Csr {
    off: Vec<u32>,
    data: Vec<u32>,
}

impl Csr {
    pub fn new() -> Self {
        Self {
            off: vec![0],
            data: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push_row(&mut self, row: &[u32]) {
        self.data.extend_from_slice(row);
        self.off.push(self.data.len() as u32);
    }

    /// Row `i`; empty when out of range.
    #[inline]
    pub fn row(&self, i: u32) -> &[u32] {
        let i = i as usize;
        match (self.off.get(i), self.off.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.data[a as usize..b as usize],
            _ => &[],
        }
    }

    /// First position of row `i` in [`Csr::data`].
    #[inline]
    pub fn row_start(&self, i: u32) -> usize {
        self.off.get(i as usize).map_or(0, |&a| a as usize)
    }

    pub fn rows(&self) -> usize {
        self.off.len().saturating_sub(1)
    }

    pub fn data(&self) -> &[u32] {
        &self.data
    }

    /// Builds the transposed relation: for `rows` rows, the list of `(row, value)` pairs given
    /// by `pairs`, each row keeping the order in which its pairs come.
    pub fn from_pairs(rows: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        let mut off = vec![0u32; rows + 1];
        for (r, _) in pairs.clone() {
            off[r as usize + 1] += 1;
        }
        for i in 0..rows {
            off[i + 1] += off[i];
        }
        let mut fill: Vec<u32> = off[..rows].to_vec();
        let mut data = vec![0u32; off[rows] as usize];
        for (r, v) in pairs {
            let slot = &mut fill[r as usize];
            data[*slot as usize] = v;
            *slot += 1;
        }
        Self { off, data }
    }

    /// Heap bytes used.
    pub fn heap_bytes(&self) -> usize {
        (self.off.capacity() + self.data.capacity()) * 4
    }
}

/// String interner: every label, state, ingredient, container and motion is stored once, in
/// one text buffer with end offsets; the hash table holds only ids.
#[derive(Debug, Clone, Default)]
pub struct Interner {
    text: String,
    ends: Vec<u64>,
    table: HashTable<u32>,
}

fn hash_str(s: &str) -> u64 {
    let mut h = FxHasher::default();
    h.write(s.as_bytes());
    h.finish()
}

fn slice<'a>(text: &'a str, ends: &[u64], id: u32) -> &'a str {
    let i = id as usize;
    let Some(&end) = ends.get(i) else { return "" };
    let start = if i == 0 { 0 } else { ends[i - 1] };
    text.get(start as usize..end as usize).unwrap_or("")
}

impl Interner {
    pub fn intern(&mut self, s: &str) -> u32 {
        let h = hash_str(s);
        let (text, ends) = (&self.text, &self.ends);
        if let Some(&id) = self.table.find(h, |&id| slice(text, ends, id) == s) {
            return id;
        }
        let id = self.ends.len() as u32;
        self.text.push_str(s);
        self.ends.push(self.text.len() as u64);
        let (text, ends) = (&self.text, &self.ends);
        self.table
            .insert_unique(h, id, |&id| hash_str(slice(text, ends, id)));
        id
    }

    pub fn get(&self, s: &str) -> Option<u32> {
        let (text, ends) = (&self.text, &self.ends);
        self.table
            .find(hash_str(s), |&id| slice(text, ends, id) == s)
            .copied()
    }

    /// The text of id `id` (empty for [`NONE`] or an unknown id).
    #[inline]
    pub fn text(&self, id: u32) -> &str {
        slice(&self.text, &self.ends, id)
    }

    pub fn len(&self) -> usize {
        self.ends.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Heap bytes used.
    pub fn heap_bytes(&self) -> usize {
        self.text.capacity() + self.ends.capacity() * 8 + self.table.capacity() * 5
    }
}

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

/// An FU dropped because it repeats an earlier one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DuplicateFu {
    /// Line where the dropped copy starts.
    pub line: u32,
    /// Index of the kept copy.
    pub of: u32,
}

/// A parsed FOON: immutable once built, `Send + Sync`, shared behind `Arc`.
#[derive(Debug, Clone, Default)]
pub struct Foon {
    pub(crate) strings: Interner,
    // Objects, by id: canonical identity (states and ingredients sorted by string id).
    pub(crate) obj_label: Vec<u32>,
    pub(crate) obj_container: Vec<u32>,
    pub(crate) obj_states: Csr,
    pub(crate) obj_ingredients: Csr,
    pub(crate) obj_first_variant: Vec<u32>,
    // Variants: an object as written somewhere (its own state and ingredient order).
    pub(crate) var_obj: Vec<u32>,
    pub(crate) var_states: Csr,
    pub(crate) var_ingredients: Csr,
    // FUs, by index (file order after dropping faulty and duplicate FUs).
    pub(crate) fu_motion: Vec<u32>,
    pub(crate) fu_motion_meta: Vec<u32>,
    pub(crate) fu_line: Vec<u32>,
    pub(crate) fu_inputs: Csr,
    pub(crate) fu_outputs: Csr,
    pub(crate) fu_input_variant: Vec<u32>,
    pub(crate) fu_output_variant: Vec<u32>,
    pub(crate) fu_input_in_motion: Vec<u8>,
    pub(crate) fu_output_in_motion: Vec<u8>,
    // Adjacency.
    pub(crate) producers: Csr,
    pub(crate) consumers: Csr,
    pub(crate) motions: Vec<u32>,
    /// Object ids, hashed by identity (see [`identity_hash`]).
    pub(crate) identity: HashTable<u32>,
    /// FU indices, hashed by FU identity (see [`fu_key_into`]).
    pub(crate) fu_identity: HashTable<u32>,
    // Load report.
    pub(crate) warnings: Vec<Warning>,
    /// Lint notes found while parsing (not warnings: strict mode ignores them).
    pub(crate) notes: Vec<Warning>,
    pub(crate) duplicates: Vec<DuplicateFu>,
    pub(crate) source: Option<PathBuf>,
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

    pub fn source(&self) -> Option<&std::path::Path> {
        self.source.as_deref()
    }

    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Lint notes found while parsing (spaced or repeated ingredients, empty containers).
    pub fn notes(&self) -> &[Warning] {
        &self.notes
    }

    pub fn duplicates(&self) -> &[DuplicateFu] {
        &self.duplicates
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
        let h = identity_hash(label, container, states, ingredients);
        self.identity
            .find(h, |&o| {
                self.same_object(o, label, states, ingredients, container)
            })
            .copied()
    }

    fn same_object(
        &self,
        o: u32,
        label: u32,
        states: &[u32],
        ingredients: &[u32],
        container: u32,
    ) -> bool {
        self.obj_label[o as usize] == label
            && self.obj_container[o as usize] == container
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

    /// Objects whose label is `label`, in id order.
    pub fn objects_with_label(&self, label: &str) -> Vec<u32> {
        let Some(l) = self.strings.get(label) else {
            return Vec::new();
        };
        (0..self.object_count() as u32)
            .filter(|&o| self.obj_label[o as usize] == l)
            .collect()
    }

    /// The FU with this identity (motion string id, and inputs and outputs as object ids
    /// in any order: multisets), if there is one. The identity is the one that drops
    /// duplicate FUs on load.
    pub fn find_fu(&self, motion: u32, inputs: &[u32], outputs: &[u32]) -> Option<u32> {
        let mut key = Vec::new();
        fu_key_into(motion, inputs, outputs, &mut key);
        let mut scratch = Vec::new();
        self.fu_identity
            .find(slice_hash(&key), |&g| {
                fu_key_into(
                    self.fu_motion[g as usize],
                    self.inputs(g),
                    self.outputs(g),
                    &mut scratch,
                );
                scratch == key
            })
            .copied()
    }

    /// The goal object for a spec: the object with its identity, or
    /// [`Error::GoalNotFound`] ("The goal node does not exist: ...").
    pub fn goal_by_spec(&self, spec: &ObjectSpec) -> Result<u32> {
        spec.find_in(self).ok_or_else(|| Error::GoalNotFound {
            goal: spec.describe(),
        })
    }

    /// The goal object for a label that exactly one object has; [`Error::GoalNotFound`]
    /// when none has it, [`Error::GoalAmbiguous`] (one line, at most five objects shown)
    /// when several have it.
    pub fn goal_by_label(&self, label: &str) -> Result<u32> {
        const SHOWN: usize = 5;
        let ids = self.objects_with_label(label);
        match ids.as_slice() {
            [] => Err(Error::GoalNotFound {
                goal: label.to_owned(),
            }),
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
            })
        }
    }

    pub fn stats(&self) -> Stats {
        let produced = (0..self.object_count() as u32)
            .filter(|&o| !self.producers(o).is_empty())
            .count();
        let index_bytes = self.fu_inputs.heap_bytes()
            + self.fu_outputs.heap_bytes()
            + self.producers.heap_bytes()
            + self.consumers.heap_bytes()
            + self.obj_states.heap_bytes()
            + self.obj_ingredients.heap_bytes()
            + (self.obj_label.capacity() + self.obj_container.capacity()) * 4
            + (self.fu_motion.capacity() + self.fu_line.capacity()) * 4
            + self.strings.heap_bytes()
            + (self.identity.capacity() + self.fu_identity.capacity()) * 5;
        Stats {
            functional_units: self.fu_count(),
            objects: self.object_count(),
            produced_objects: produced,
            motions: self.motions.len(),
            strings: self.strings.len(),
            input_edges: self.fu_inputs.data().len(),
            output_edges: self.fu_outputs.data().len(),
            duplicates_dropped: self.duplicates.len(),
            warnings: self.warnings.len(),
            index_bytes,
        }
    }
}

/// Hash of an object identity: label, container, states and ingredients (each sorted by id).
pub(crate) fn identity_hash(
    label: u32,
    container: u32,
    states: &[u32],
    ingredients: &[u32],
) -> u64 {
    let mut h = FxHasher::default();
    h.write_u32(label);
    h.write_u32(container);
    h.write_usize(states.len());
    for &x in states.iter().chain(ingredients) {
        h.write_u32(x);
    }
    h.finish()
}

/// The identity key of an FU: its motion, the number of inputs, the inputs sorted, the
/// outputs sorted (SEMANTICS §2: same motion, same multisets of inputs and of outputs).
fn fu_key_into(motion: u32, inputs: &[u32], outputs: &[u32], key: &mut Vec<u32>) {
    key.clear();
    key.push(motion);
    key.push(inputs.len() as u32);
    key.extend_from_slice(inputs);
    key[2..].sort_unstable();
    let s = key.len();
    key.extend_from_slice(outputs);
    key[s..].sort_unstable();
}

fn variant_hash(obj: u32, states: &[u32], ingredients: &[u32]) -> u64 {
    identity_hash(obj, 0, states, ingredients)
}

fn slice_hash(key: &[u32]) -> u64 {
    let mut h = FxHasher::default();
    for &x in key {
        h.write_u32(x);
    }
    h.finish()
}

/// Incremental construction of a [`Foon`]; used by the parser (and later by merging).
#[derive(Debug, Default)]
pub struct Builder {
    foon: Foon,
    /// Variant ids hashed by (object, states and ingredients in written order).
    variants: HashTable<u32>,
    scratch: Vec<u32>,
    motion_seen: Vec<bool>,
    id_key: Vec<u32>,
    fu_key: Vec<u32>,
    ins: Vec<u32>,
    outs: Vec<u32>,
    in_vars: Vec<u32>,
    out_vars: Vec<u32>,
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
        ] {
            *csr = Csr::new();
        }
        b
    }

    pub fn intern(&mut self, s: &str) -> u32 {
        self.foon.strings.intern(s)
    }

    pub fn text(&self, id: u32) -> &str {
        self.foon.strings.text(id)
    }

    pub fn fu_count(&self) -> usize {
        self.foon.fu_count()
    }

    /// Interns an object occurrence; returns `(object id, variant id)`.
    fn object(&mut self, raw: &RawObject<'_>) -> (u32, u32) {
        // Canonical form: states then ingredients, each sorted by id, in one scratch buffer.
        let key = &mut self.id_key;
        let ns = canonical_into(raw.states, raw.ingredients, key);
        let (states, ingredients) = key.split_at(ns);
        let f = &mut self.foon;
        let obj = if let Some(o) = f.find_sorted(raw.label, states, ingredients, raw.container) {
            o
        } else {
            let o = f.obj_label.len() as u32;
            f.obj_label.push(raw.label);
            f.obj_container.push(raw.container);
            f.obj_states.push_row(states);
            f.obj_ingredients.push_row(ingredients);
            f.obj_first_variant.push(NONE);
            let h = identity_hash(raw.label, raw.container, states, ingredients);
            let (labels, conts, st, ing) = (
                &f.obj_label,
                &f.obj_container,
                &f.obj_states,
                &f.obj_ingredients,
            );
            f.identity.insert_unique(h, o, |&x| {
                identity_hash(labels[x as usize], conts[x as usize], st.row(x), ing.row(x))
            });
            o
        };
        let vh = variant_hash(obj, raw.states, raw.ingredients);
        let (vo, vs, vi) = (&f.var_obj, &f.var_states, &f.var_ingredients);
        let found = self.variants.find(vh, |&v| {
            vo[v as usize] == obj && vs.row(v) == raw.states && vi.row(v) == raw.ingredients
        });
        let var = if let Some(&v) = found {
            v
        } else {
            let v = f.var_obj.len() as u32;
            f.var_obj.push(obj);
            f.var_states.push_row(raw.states);
            f.var_ingredients.push_row(raw.ingredients);
            let (vo, vs, vi) = (&f.var_obj, &f.var_states, &f.var_ingredients);
            self.variants.insert_unique(vh, v, |&x| {
                variant_hash(vo[x as usize], vs.row(x), vi.row(x))
            });
            v
        };
        if f.obj_first_variant[obj as usize] == NONE {
            f.obj_first_variant[obj as usize] = var;
        }
        (obj, var)
    }

    /// Adds an FU; returns its index, or the index of the earlier equal FU when it is a
    /// duplicate (`Err`), in which case it is recorded and dropped.
    pub fn add_fu(
        &mut self,
        motion: u32,
        motion_meta: u32,
        inputs: &[RawObject<'_>],
        outputs: &[RawObject<'_>],
        line: u32,
    ) -> Result<u32, u32> {
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
        for raw in inputs {
            let (o, v) = self.object(raw);
            in_ids.push(o);
            in_vars.push(v);
        }
        for raw in outputs {
            let (o, v) = self.object(raw);
            out_ids.push(o);
            out_vars.push(v);
        }
        fu_key_into(motion, &in_ids, &out_ids, &mut key);
        let h = slice_hash(&key);
        let f = &self.foon;
        let scratch = &mut self.scratch;
        let found = f.fu_identity.find(h, |&g| {
            fu_key_into(
                f.fu_motion[g as usize],
                f.fu_inputs.row(g),
                f.fu_outputs.row(g),
                scratch,
            );
            *scratch == key
        });
        let result = if let Some(&first) = found {
            self.foon.duplicates.push(DuplicateFu { line, of: first });
            Err(first)
        } else {
            let f = &mut self.foon;
            let idx = f.fu_motion.len() as u32;
            f.fu_motion.push(motion);
            f.fu_motion_meta.push(motion_meta);
            f.fu_line.push(line);
            f.fu_inputs.push_row(&in_ids);
            f.fu_outputs.push_row(&out_ids);
            f.fu_input_variant.extend_from_slice(&in_vars);
            f.fu_output_variant.extend_from_slice(&out_vars);
            f.fu_input_in_motion
                .extend(inputs.iter().map(|r| r.in_motion));
            f.fu_output_in_motion
                .extend(outputs.iter().map(|r| r.in_motion));
            let (motions, ins, outs) = (&f.fu_motion, &f.fu_inputs, &f.fu_outputs);
            // Rehashing (when the table grows) recomputes each key in one scratch buffer.
            let k = std::cell::RefCell::new(Vec::new());
            f.fu_identity.insert_unique(h, idx, |&x| {
                let mut k = k.borrow_mut();
                fu_key_into(motions[x as usize], ins.row(x), outs.row(x), &mut k);
                slice_hash(&k)
            });
            let m = motion as usize;
            if self.motion_seen.len() <= m {
                self.motion_seen.resize(m + 1, false);
            }
            if !self.motion_seen[m] {
                self.motion_seen[m] = true;
                f.motions.push(motion);
            }
            Ok(idx)
        };
        self.ins = in_ids;
        self.outs = out_ids;
        self.in_vars = in_vars;
        self.out_vars = out_vars;
        self.fu_key = key;
        result
    }

    pub fn warn(&mut self, w: Warning) {
        self.foon.warnings.push(w);
    }

    pub fn note(&mut self, w: Warning) {
        self.foon.notes.push(w);
    }

    /// Finishes the index: builds producers (course rule) and consumers.
    pub fn finish(self, source: Option<PathBuf>) -> Foon {
        let mut f = self.foon;
        f.source = source;
        let n_obj = f.obj_label.len();
        let n_fu = f.fu_motion.len() as u32;
        let outs = &f.fu_outputs;
        let bare: Vec<bool> = (0..n_obj as u32)
            .map(|o| {
                f.obj_states.row(o).is_empty()
                    && f.obj_ingredients.row(o).is_empty()
                    && f.obj_container[o as usize] == NONE
            })
            .collect();
        // An FU that outputs the same object twice is listed once as its producer.
        let prod_pairs = (0..n_fu).flat_map(|fu| {
            let row = outs.row(fu);
            row.iter()
                .enumerate()
                .filter(|&(k, &o)| !bare[o as usize] && !row[..k].contains(&o))
                .map(move |(_, &o)| (o, fu))
        });
        f.producers = Csr::from_pairs(n_obj, prod_pairs);
        let ins = &f.fu_inputs;
        let cons_pairs = (0..n_fu).flat_map(|fu| ins.row(fu).iter().map(move |&o| (o, fu)));
        f.consumers = Csr::from_pairs(n_obj, cons_pairs);
        f
    }
}

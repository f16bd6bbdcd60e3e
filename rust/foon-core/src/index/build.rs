//! Building a [`Foon`]: objects interned by identity and their written variants, FUs with
//! duplicates dropped, then the producer and consumer lists.

use std::path::PathBuf;

use hashbrown::HashTable;

use super::{Csr, DuplicateFu, Foon, NONE, fu_key_into, identity_hash, slice_hash};
use crate::error::Warning;
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

fn variant_hash(obj: u32, states: &[u32], ingredients: &[u32]) -> u64 {
    identity_hash(obj, 0, states, ingredients)
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

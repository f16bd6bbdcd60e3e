//! Building a [`Foon`]: objects interned by identity and their written variants, FUs with
//! duplicates dropped, then the producer and consumer lists.

use std::path::Path;

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
    /// The source FUs are being read from (set by [`Builder::begin_source`]).
    current: u32,
    /// Further origins of kept FUs: (FU, source, line).
    also: Vec<(u32, u32, u32)>,
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

    /// Starts a new source (a file, or text given in memory when `path` is `None`): the FUs
    /// added from now on come from it. Returns its id.
    pub fn begin_source(&mut self, path: Option<&Path>) -> u32 {
        let id = self.foon.sources.len() as u32;
        self.foon.sources.push(
            path.map(|p| p.to_string_lossy().into_owned())
                .unwrap_or_default(),
        );
        self.current = id;
        id
    }

    /// Records that FU `fu` was also found in `source` at `line` (merging).
    pub fn add_origin(&mut self, fu: u32, source: u32, line: u32) {
        self.also.push((fu, source, line));
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
            let source = self.current;
            self.foon.report.duplicates.push(DuplicateFu {
                line,
                of: first,
                source,
            });
            self.also.push((first, source, line));
            Err(first)
        } else {
            let f = &mut self.foon;
            let idx = f.fu_motion.len() as u32;
            f.fu_motion.push(motion);
            f.fu_motion_meta.push(motion_meta);
            f.fu_line.push(line);
            f.fu_source.push(self.current);
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
        self.foon.report.warnings.push(w);
    }

    pub fn note(&mut self, w: Warning) {
        self.foon.report.notes.push(w);
    }

    /// Finishes the index: builds producers (course rule), consumers and the provenance rows.
    pub fn finish(self) -> Foon {
        let mut f = self.foon;
        if f.sources.is_empty() {
            f.sources.push(String::new());
        }
        let mut also = Csr::new();
        let mut pairs = Vec::new();
        let mut rest = self.also;
        rest.sort_by_key(|&(fu, _, _)| fu); // stable: each row keeps the reading order
        let mut it = rest.into_iter().peekable();
        for fu in 0..f.fu_motion.len() as u32 {
            pairs.clear();
            while let Some(&(_, s, l)) = it.peek().filter(|&&(g, _, _)| g == fu) {
                pairs.extend([s, l]);
                it.next();
            }
            also.push_row(&pairs);
        }
        f.fu_also = also;
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

//! Kitchens: the objects at hand, as a compact, immutable set of object identities.
//!
//! A [`Kitchen`] keeps its own small string table and flat `u32` columns (label, container,
//! the states then the ingredients of each item as written), not one owned [`ObjectSpec`]
//! per item, so that a kitchen of half a million items costs a few megabytes and is read,
//! matched to a FOON ([`Kitchen::match_in`]) and compared without building strings per item.
//! Items are kept in the order of their first appearance; an item whose identity (SEMANTICS
//! §2: label, container, states and ingredients as multisets) repeats an earlier one is
//! counted once. Its [`fingerprint`](Kitchen::fingerprint) names the set of identities on
//! any machine, whatever the order the items were given in.

use std::hash::Hasher;
use std::path::Path;
use std::sync::OnceLock;

use hashbrown::HashTable;
use rustc_hash::FxHasher;

use crate::error::{Error, InputKind, Result};
use crate::index::{Foon, Interner, NONE};
use crate::model::{ObjectSpec, canonical_into};

/// A set of object identities with the first written form of each (see the module
/// documentation). Built by [`Kitchen::parse`], [`Kitchen::load`] or [`Kitchen::from_specs`],
/// and never changed afterwards ([`Kitchen::with`] and [`Kitchen::without`] make new ones).
#[derive(Debug, Clone)]
pub struct Kitchen {
    strings: Interner,
    label: Vec<u32>,
    /// Container string id, or [`NONE`].
    container: Vec<u32>,
    /// Item `i`'s states are `fields[start[i]..split[i]]`, its ingredients
    /// `fields[split[i]..start[i + 1]]`, as written.
    start: Vec<u32>,
    split: Vec<u32>,
    fields: Vec<u32>,
    /// The identity hash of each item (kept, so that growing the table recomputes nothing).
    hashes: Vec<u64>,
    /// Item indices, hashed by identity.
    table: HashTable<u32>,
    /// [`Kitchen::fingerprint`] and the sum of the items' fingerprints it is made of.
    fingerprint: OnceLock<(u128, u128)>,
    /// Set when a column would pass `u32` (reported as an error by the builders).
    too_large: bool,
    /// The canonical key of the item being added (reused from item to item).
    scratch: Vec<u32>,
}

/// The identity hash of an item given by string ids of one table, its states and
/// ingredients each sorted by id (in memory only: ids depend on the table).
fn id_hash(label: u32, container: u32, states: &[u32], ingredients: &[u32]) -> u64 {
    let mut h = FxHasher::default();
    h.write_u32(label);
    h.write_u32(container);
    h.write_u32(states.len() as u32);
    for &x in states.iter().chain(ingredients) {
        h.write_u32(x);
    }
    h.finish()
}

impl Kitchen {
    /// An empty kitchen.
    pub fn new() -> Self {
        Self {
            strings: Interner::default(),
            label: Vec::new(),
            container: Vec::new(),
            start: vec![0],
            split: Vec::new(),
            fields: Vec::new(),
            hashes: Vec::new(),
            table: HashTable::new(),
            fingerprint: OnceLock::new(),
            too_large: false,
            scratch: Vec::new(),
        }
    }

    /// Parses a kitchen: a JSON list of objects or FOON object blocks, by the one grammar
    /// of [`parse_objects`](crate::parse::parse_objects) (the same errors, at the same file,
    /// line and column). `path` names the source in messages.
    pub fn parse(data: &[u8], path: Option<&Path>) -> Result<Self> {
        let mut k = Self::new();
        k.read_objects(data, path, InputKind::Kitchen)?;
        k.finish()
    }

    /// Reads a kitchen file (see [`Kitchen::parse`]).
    pub fn load(path: &Path) -> Result<Self> {
        let data = crate::parse::read_file(path)?;
        Self::parse(&data, Some(path))
    }

    /// A kitchen of `specs`, in order, repeats counted once.
    pub fn from_specs<'a>(specs: impl IntoIterator<Item = &'a ObjectSpec>) -> Result<Self> {
        let mut k = Self::new();
        for s in specs {
            k.push_spec(s);
        }
        k.finish()
    }

    fn finish(mut self) -> Result<Self> {
        if self.too_large {
            return Err(Error::Invalid(
                "the kitchen is too large (more than 2^32 - 1 items or fields)".into(),
            ));
        }
        self.shrink();
        Ok(self)
    }

    fn shrink(&mut self) {
        self.label.shrink_to_fit();
        self.container.shrink_to_fit();
        self.start.shrink_to_fit();
        self.split.shrink_to_fit();
        self.fields.shrink_to_fit();
        self.hashes.shrink_to_fit();
    }

    fn push_spec(&mut self, s: &ObjectSpec) -> bool {
        self.push(
            &s.label,
            s.states.iter().map(String::as_str),
            s.ingredients.iter().map(String::as_str),
            s.container.as_deref(),
        )
    }

    /// Adds an item unless its identity is already here; whether it was added.
    pub(crate) fn push<'a>(
        &mut self,
        label: &'a str,
        states: impl Iterator<Item = &'a str>,
        ingredients: impl Iterator<Item = &'a str>,
        container: Option<&'a str>,
    ) -> bool {
        let first = self.fields.len();
        let label = self.strings.intern(label);
        let container = container.map_or(NONE, |c| self.strings.intern(c));
        for s in states {
            let id = self.strings.intern(s);
            self.fields.push(id);
        }
        let split = self.fields.len();
        for s in ingredients {
            let id = self.strings.intern(s);
            self.fields.push(id);
        }
        let mut key = std::mem::take(&mut self.scratch);
        let ns = canonical_into(&self.fields[first..split], &self.fields[split..], &mut key);
        let (st, ing) = key.split_at(ns);
        let h = id_hash(label, container, st, ing);
        let found = self.find_ids(h, label, container, st, ing).is_some();
        self.scratch = key;
        if found {
            self.fields.truncate(first);
            return false;
        }
        let (Ok(item), Ok(end), Ok(split)) = (
            u32::try_from(self.label.len()),
            u32::try_from(self.fields.len()),
            u32::try_from(split),
        ) else {
            self.fields.truncate(first);
            self.too_large = true;
            return false;
        };
        if item == NONE {
            self.fields.truncate(first);
            self.too_large = true;
            return false;
        }
        self.label.push(label);
        self.container.push(container);
        self.split.push(split);
        self.start.push(end);
        self.hashes.push(h);
        let hashes = &self.hashes;
        self.table.insert_unique(h, item, |&i| hashes[i as usize]);
        true
    }

    /// The item with this identity (string ids of this kitchen, sorted), if any.
    fn find_ids(
        &self,
        h: u64,
        label: u32,
        container: u32,
        states: &[u32],
        ingredients: &[u32],
    ) -> Option<usize> {
        let mut key = Vec::new();
        self.table
            .find(h, |&i| {
                let i = i as usize;
                if self.label[i] != label || self.container[i] != container {
                    return false;
                }
                let (s, g) = self.ids(i);
                if s.len() != states.len() || g.len() != ingredients.len() {
                    return false;
                }
                let ns = canonical_into(s, g, &mut key);
                key[..ns] == *states && key[ns..] == *ingredients
            })
            .map(|&i| i as usize)
    }

    /// String ids of item `i`'s states and ingredients, as written.
    fn ids(&self, i: usize) -> (&[u32], &[u32]) {
        let (a, m, b) = (
            self.start[i] as usize,
            self.split[i] as usize,
            self.start[i + 1] as usize,
        );
        (&self.fields[a..m], &self.fields[m..b])
    }

    /// Number of items (distinct identities).
    pub fn len(&self) -> usize {
        self.label.len()
    }

    /// Whether the kitchen has no item.
    pub fn is_empty(&self) -> bool {
        self.label.is_empty()
    }

    /// Number of distinct strings (labels, states, ingredients, containers) of the items.
    pub fn string_count(&self) -> usize {
        self.strings.len()
    }

    /// Heap bytes used by the columns and the string table.
    pub fn heap_bytes(&self) -> usize {
        self.strings.heap_bytes()
            + 4 * (self.label.capacity()
                + self.container.capacity()
                + self.start.capacity()
                + self.split.capacity()
                + self.fields.capacity())
            + 8 * self.hashes.capacity()
            + 5 * self.table.capacity()
    }

    /// Item `i`'s label (`i < len()`).
    pub fn label(&self, i: usize) -> &str {
        self.strings.text(self.label[i])
    }

    /// Item `i`'s container, if it has one.
    pub fn container(&self, i: usize) -> Option<&str> {
        let c = self.container[i];
        (c != NONE).then(|| self.strings.text(c))
    }

    /// Item `i`'s states, as first written.
    pub fn states(&self, i: usize) -> impl ExactSizeIterator<Item = &str> + '_ {
        self.ids(i).0.iter().map(|&s| self.strings.text(s))
    }

    /// Item `i`'s ingredients, as first written.
    pub fn ingredients(&self, i: usize) -> impl ExactSizeIterator<Item = &str> + '_ {
        self.ids(i).1.iter().map(|&s| self.strings.text(s))
    }

    /// Item `i` as a spec, in its first written form (`None` past the end).
    pub fn get(&self, i: usize) -> Option<ObjectSpec> {
        (i < self.len()).then(|| self.spec(i))
    }

    fn spec(&self, i: usize) -> ObjectSpec {
        ObjectSpec {
            label: self.label(i).to_owned(),
            states: self.states(i).map(str::to_owned).collect(),
            ingredients: self.ingredients(i).map(str::to_owned).collect(),
            container: self.container(i).map(str::to_owned),
        }
    }

    /// The items as specs, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = ObjectSpec> + '_ {
        (0..self.len()).map(|i| self.spec(i))
    }

    /// The items as specs, in order (for the interfaces that take a list).
    pub fn specs(&self) -> Vec<ObjectSpec> {
        self.iter().collect()
    }

    /// The index of the item with the identity of `spec`, if there is one.
    pub fn position(&self, spec: &ObjectSpec) -> Option<usize> {
        let get = |s: &str| self.strings.get(s);
        let label = get(&spec.label)?;
        let container = match &spec.container {
            Some(c) => get(c)?,
            None => NONE,
        };
        self.find_mapped(
            label,
            container,
            spec.states.iter().map(|s| get(s)),
            spec.ingredients.iter().map(|s| get(s)),
        )
    }

    /// The index of the item with this identity, its fields already string ids of `self`
    /// (`None` for a string `self` does not have: then no item has it).
    fn find_mapped(
        &self,
        label: u32,
        container: u32,
        states: impl Iterator<Item = Option<u32>>,
        ingredients: impl Iterator<Item = Option<u32>>,
    ) -> Option<usize> {
        let s: Option<Vec<u32>> = states.collect();
        let g: Option<Vec<u32>> = ingredients.collect();
        let mut key = Vec::new();
        let ns = canonical_into(&s?, &g?, &mut key);
        let (st, ing) = key.split_at(ns);
        self.find_ids(
            id_hash(label, container, st, ing),
            label,
            container,
            st,
            ing,
        )
    }

    /// Whether an item has the identity of `spec`.
    pub fn contains(&self, spec: &ObjectSpec) -> bool {
        self.position(spec).is_some()
    }

    /// Whether item `i` of `self` is an item of `other`.
    fn item_in(&self, i: usize, other: &Self) -> bool {
        other.position_of(self, i).is_some()
    }

    /// The index in `self` of item `i` of `from` (looked up by text, not allocated).
    fn position_of(&self, from: &Self, i: usize) -> Option<usize> {
        let map = |id: u32| self.strings.get(from.strings.text(id));
        let label = map(from.label[i])?;
        let container = match from.container[i] {
            NONE => NONE,
            c => map(c)?,
        };
        let (s, g) = from.ids(i);
        self.find_mapped(
            label,
            container,
            s.iter().map(|&x| map(x)),
            g.iter().map(|&x| map(x)),
        )
    }

    /// Copies item `i` of `from` into `self` (unless its identity is here already); whether
    /// it was added.
    fn push_item(&mut self, from: &Self, i: usize) -> bool {
        self.push(
            from.label(i),
            from.states(i),
            from.ingredients(i),
            from.container(i),
        )
    }

    /// A kitchen of the items of `self` whose identity is not an item of `drop`, in order.
    #[must_use]
    pub fn without(&self, drop: &Self) -> Self {
        let mut k = Self::new();
        for i in 0..self.len() {
            if !self.item_in(i, drop) {
                k.push_item(self, i);
            }
        }
        k.shrink();
        k
    }

    /// A kitchen of the items of `self`, then those of `add` that are not in it.
    pub fn with(&self, add: &Self) -> Result<Self> {
        let mut k = self.clone();
        k.fingerprint = OnceLock::new();
        for i in 0..add.len() {
            k.push_item(add, i);
        }
        k.finish()
    }

    /// The kitchen after a chain of changes, each `(add, remove)` step [`Kitchen::without`]
    /// the items of `remove`, then [`Kitchen::with`] those of `add`: the same items, in the
    /// same order and forms, as those calls made step after step, in time proportional to
    /// the items of `self` and of the steps rather than to the steps times the kitchen.
    pub fn with_steps(&self, steps: &[(&Self, &Self)]) -> Result<Self> {
        // Every identity seen (the items of `seen`, in the order first seen), with whether it
        // is in the kitchen, when it last came in (the order of the result) and the item it
        // came in as (its form): (0, i) for item i of `self`, (s + 1, i) for item i of step
        // s's `add`.
        let mut seen = self.clone();
        let n = self.len();
        let mut present = vec![true; n];
        let mut since: Vec<usize> = (0..n).collect();
        let mut form: Vec<(usize, usize)> = (0..n).map(|i| (0, i)).collect();
        let mut clock = n;
        for (s, &(add, remove)) in steps.iter().enumerate() {
            for r in 0..remove.len() {
                if let Some(j) = seen.position_of(remove, r) {
                    present[j] = false;
                }
            }
            for a in 0..add.len() {
                let j = match seen.position_of(add, a) {
                    Some(j) if present[j] => continue,
                    Some(j) => j,
                    None => {
                        if !seen.push_item(add, a) {
                            // An identity not found is added unless the kitchen is too large
                            // for its columns: that error.
                            seen.too_large = true;
                            return seen.finish();
                        }
                        present.push(true);
                        since.push(0);
                        form.push((0, 0));
                        present.len() - 1
                    }
                };
                present[j] = true;
                since[j] = clock;
                form[j] = (s + 1, a);
                clock += 1;
            }
        }
        let mut order: Vec<usize> = (0..present.len()).filter(|&j| present[j]).collect();
        order.sort_unstable_by_key(|&j| since[j]);
        let mut k = Self::new();
        for j in order {
            let (from, i) = form[j];
            k.push_item(if from == 0 { self } else { steps[from - 1].0 }, i);
        }
        k.finish()
    }

    /// The object ids of `foon` whose identity is an item's, sorted, each once (level 3 of
    /// [`Kitchen::match_many`]).
    pub fn match_in(&self, foon: &Foon) -> Vec<u32> {
        let mut out = Self::match_level3(&[self], foon);
        out.pop().unwrap_or_default()
    }

    /// The object ids of `foon` equal to an item at identity `level` (3: [`Kitchen::match_in`];
    /// 2 and 1: [`level_key`](crate::merge::level_key), the levels of merging), sorted, each
    /// once. An item with a label or container the FOON lacks matches nothing; at level 2, one
    /// with a state the FOON lacks matches nothing either.
    pub fn match_at_level(&self, foon: &Foon, level: u8) -> Result<Vec<u32>> {
        let mut out = Self::match_many(&[self], foon, level)?;
        Ok(out.pop().unwrap_or_default())
    }

    /// [`Kitchen::match_at_level`] of each kitchen, in order: the one place kitchens are
    /// matched to a FOON. Each distinct string of the kitchens is looked up once in the FOON's
    /// string table, and at level 3 each distinct item once in its object table (kitchens of
    /// one household share most of their items, and a look-up in a large FOON is a few cache
    /// misses, while the kitchens' own memo stays in cache); at levels 1 and 2 the FOON's
    /// objects are scanned once for all the kitchens.
    pub fn match_many(kitchens: &[&Kitchen], foon: &Foon, level: u8) -> Result<Vec<Vec<u32>>> {
        match level {
            3 => Ok(Self::match_level3(kitchens, foon)),
            1 | 2 => Ok(Self::match_coarse(kitchens, foon, level)),
            _ => Err(crate::Error::Invalid(format!(
                "level must be 1, 2 or 3 (got {level})"
            ))),
        }
    }

    /// Each kitchen's string ids mapped to `foon`'s ([`NONE`]: not in the FOON), each distinct
    /// text looked up once.
    fn string_maps<'k>(kitchens: &[&'k Kitchen], foon: &Foon) -> Vec<Vec<u32>> {
        let table = foon.strings();
        let mut memo: rustc_hash::FxHashMap<&'k str, u32> = rustc_hash::FxHashMap::default();
        kitchens
            .iter()
            .map(|k| {
                (0..k.strings.len() as u32)
                    .map(|id| {
                        let text = k.strings.text(id);
                        if kitchens.len() == 1 {
                            return table.get(text).unwrap_or(NONE);
                        }
                        *memo
                            .entry(text)
                            .or_insert_with(|| table.get(text).unwrap_or(NONE))
                    })
                    .collect()
            })
            .collect()
    }

    /// Level 3: full identity. An item with a string the FOON lacks is skipped without a
    /// look-up.
    fn match_level3(kitchens: &[&Kitchen], foon: &Foon) -> Vec<Vec<u32>> {
        let maps = Self::string_maps(kitchens, foon);
        // Distinct items of all the kitchens (as FOON string ids: label, container, the
        // number of states, then states and ingredients sorted) -> object id or NONE.
        let mut memo: rustc_hash::FxHashMap<Box<[u32]>, u32> = rustc_hash::FxHashMap::default();
        let shared = kitchens.len() > 1;
        let (mut st, mut ing, mut key) = (Vec::new(), Vec::new(), Vec::new());
        let mut full: Vec<u32> = Vec::new();
        kitchens
            .iter()
            .zip(&maps)
            .map(|(k, map)| {
                let mut ids = Vec::new();
                'items: for i in 0..k.len() {
                    let label = map[k.label[i] as usize];
                    let container = match k.container[i] {
                        NONE => NONE,
                        c => map[c as usize],
                    };
                    if label == NONE || (container == NONE && k.container[i] != NONE) {
                        continue;
                    }
                    let (s, g) = k.ids(i);
                    st.clear();
                    ing.clear();
                    for (src, dst) in [(s, &mut st), (g, &mut ing)] {
                        for &x in src {
                            let m = map[x as usize];
                            if m == NONE {
                                continue 'items;
                            }
                            dst.push(m);
                        }
                    }
                    let ns = canonical_into(&st, &ing, &mut key);
                    let (a, b) = key.split_at(ns);
                    let found = if shared {
                        full.clear();
                        full.extend_from_slice(&[label, container, ns as u32]);
                        full.extend_from_slice(&key);
                        if let Some(&o) = memo.get(full.as_slice()) {
                            o
                        } else {
                            let o = foon.find_sorted(label, a, b, container).unwrap_or(NONE);
                            memo.insert(full.as_slice().into(), o);
                            o
                        }
                    } else {
                        foon.find_sorted(label, a, b, container).unwrap_or(NONE)
                    };
                    if found != NONE {
                        ids.push(found);
                    }
                }
                ids.sort_unstable();
                ids.dedup();
                ids
            })
            .collect()
    }

    /// Levels 1 and 2: the kitchens' level keys, then one scan of the FOON's objects.
    fn match_coarse(kitchens: &[&Kitchen], foon: &Foon, level: u8) -> Vec<Vec<u32>> {
        use crate::merge::{level_key, object_level_key};
        let maps = Self::string_maps(kitchens, foon);
        // Level key -> the kitchens that hold it (sorted, each once).
        let mut keys: rustc_hash::FxHashMap<(u32, u32, Vec<u32>), Vec<u32>> =
            rustc_hash::FxHashMap::default();
        for (ki, (k, map)) in kitchens.iter().zip(&maps).enumerate() {
            let map = |id: u32| map[id as usize];
            'items: for i in 0..k.len() {
                let label = map(k.label[i]);
                let container = match k.container[i] {
                    NONE => NONE,
                    c => map(c),
                };
                if label == NONE || (container == NONE && k.container[i] != NONE && level == 2) {
                    continue;
                }
                let mut states = Vec::new();
                if level == 2 {
                    for &x in k.ids(i).0 {
                        let m = map(x);
                        if m == NONE {
                            continue 'items;
                        }
                        states.push(m);
                    }
                    states.sort_unstable();
                }
                let (l, c, s) = level_key(level, label, container, &states);
                let holders = keys.entry((l, c, s.to_vec())).or_default();
                if holders.last() != Some(&(ki as u32)) {
                    holders.push(ki as u32);
                }
            }
        }
        let mut out = vec![Vec::new(); kitchens.len()];
        let mut probe = (0, 0, Vec::new());
        for o in 0..foon.object_count() as u32 {
            let (l, c, s) = object_level_key(foon, level, o);
            probe.0 = l;
            probe.1 = c;
            probe.2.clear();
            probe.2.extend_from_slice(s);
            if let Some(holders) = keys.get(&probe) {
                for &ki in holders {
                    out[ki as usize].push(o);
                }
            }
        }
        out
    }

    /// A fixed-width fingerprint of the set of identities: the same on every platform and
    /// for every order the items were given in (a seeded 128-bit hash of each identity, the
    /// strings length-prefixed and the multisets sorted by text, summed over the items, then
    /// mixed with their number). Computed once, on first use. Not a cryptographic hash.
    pub fn fingerprint(&self) -> u128 {
        self.fingerprints().0
    }

    /// [`Kitchen::fingerprint`] and the sum of the items' fingerprints (computed once).
    fn fingerprints(&self) -> (u128, u128) {
        *self.fingerprint.get_or_init(|| {
            let mut strs: Vec<&str> = Vec::new();
            let mut sum = 0u128;
            for i in 0..self.len() {
                sum = sum.wrapping_add(self.item_fingerprint(i, &mut strs));
            }
            (set_fingerprint(self.len(), sum), sum)
        })
    }

    /// The fingerprint of item `i`'s identity (`strs` is scratch space).
    fn item_fingerprint<'s>(&'s self, i: usize, strs: &mut Vec<&'s str>) -> u128 {
        let mut h = Fp::new();
        h.str(self.label(i));
        match self.container(i) {
            Some(c) => {
                h.u64(1);
                h.str(c);
            }
            None => h.u64(0),
        }
        for part in [self.ids(i).0, self.ids(i).1] {
            strs.clear();
            strs.extend(part.iter().map(|&s| self.strings.text(s)));
            strs.sort_unstable();
            h.u64(strs.len() as u64);
            for s in strs.iter() {
                h.str(s);
            }
        }
        h.finish()
    }

    /// The [`Kitchen::fingerprint`] of `self.without(remove).with(add)`, from this kitchen's
    /// (computed once) in the size of `add` and `remove`: the fingerprint of a set is made
    /// of the sum of its items' fingerprints.
    pub fn fingerprint_with_changes(&self, add: &Self, remove: &Self) -> u128 {
        let (_, mut sum) = self.fingerprints();
        let mut len = self.len();
        let mut strs: Vec<&str> = Vec::new();
        for i in 0..remove.len() {
            if remove.item_in(i, self) {
                len -= 1;
                sum = sum.wrapping_sub(remove.item_fingerprint(i, &mut strs));
            }
        }
        let mut strs: Vec<&str> = Vec::new();
        for i in 0..add.len() {
            // Added unless it stays: in this kitchen and not removed.
            if !add.item_in(i, self) || add.item_in(i, remove) {
                len += 1;
                sum = sum.wrapping_add(add.item_fingerprint(i, &mut strs));
            }
        }
        set_fingerprint(len, sum)
    }
}

/// The fingerprint of a set of `len` items whose fingerprints sum to `sum`.
fn set_fingerprint(len: usize, sum: u128) -> u128 {
    let mut h = Fp::new();
    h.u64(len as u64);
    h.u64(sum as u64);
    h.u64((sum >> 64) as u64);
    h.finish()
}

/// The magic of [`Kitchen::to_bytes`]: the format's name and version.
const MAGIC: &[u8; 8] = b"FOONKIT1";

/// Reads the little-endian values of a serialised form from a byte slice, any shortfall an
/// error (from `error`, which names the form): the reader of [`Kitchen::from_bytes`] and of
/// [`KitchenSet::from_bytes`](crate::queries::KitchenSet::from_bytes).
pub(crate) struct Reader<'a> {
    pub(crate) rest: &'a [u8],
    error: fn(&str) -> Error,
}

impl<'a> Reader<'a> {
    pub(crate) fn new(data: &'a [u8], error: fn(&str) -> Error) -> Self {
        Self { rest: data, error }
    }

    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        if self.rest.len() < n {
            return Err((self.error)("truncated"));
        }
        let (a, b) = self.rest.split_at(n);
        self.rest = b;
        Ok(a)
    }

    pub(crate) fn u32(&mut self) -> Result<u32> {
        let b = self.take(4)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    pub(crate) fn count(&mut self) -> Result<usize> {
        let n = self.u32()? as usize;
        // Every counted thing takes at least one byte: a larger count is a corrupt header.
        if n > self.rest.len() {
            return Err((self.error)("a count is larger than the data"));
        }
        Ok(n)
    }

    /// A length-prefixed (`u64`) run of bytes.
    pub(crate) fn blob(&mut self) -> Result<&'a [u8]> {
        let b = self.take(8)?;
        let n = u64::from_le_bytes(b.try_into().unwrap_or([0; 8]));
        let n = usize::try_from(n).map_err(|_| (self.error)("a length is too large"))?;
        self.take(n)
    }
}

fn bytes_error(why: &str) -> Error {
    Error::Invalid(format!("not a valid serialised kitchen: {why}"))
}

impl Kitchen {
    /// The kitchen as bytes (for pickling and shipping to other processes): a magic, the
    /// fingerprint, the string table (lengths, then text) and, per item, the string indices
    /// of its label, container (or `u32::MAX`), states and ingredients with their counts;
    /// all little-endian `u32`, so the same on every platform. [`Kitchen::from_bytes`] reads
    /// it back.
    pub fn to_bytes(&self) -> Vec<u8> {
        let n = self.strings.len();
        let mut out = Vec::with_capacity(
            32 + 4 * (n + 4 * self.len() + self.fields.len()) + self.strings.heap_bytes() / 2,
        );
        let put = |out: &mut Vec<u8>, x: u32| out.extend_from_slice(&x.to_le_bytes());
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&self.fingerprint().to_le_bytes());
        put(&mut out, n as u32);
        for id in 0..n as u32 {
            put(&mut out, self.strings.text(id).len() as u32);
        }
        for id in 0..n as u32 {
            out.extend_from_slice(self.strings.text(id).as_bytes());
        }
        put(&mut out, self.len() as u32);
        for i in 0..self.len() {
            let (st, ing) = self.ids(i);
            put(&mut out, self.label[i]);
            put(&mut out, self.container[i]);
            put(&mut out, st.len() as u32);
            put(&mut out, ing.len() as u32);
            for &x in st.iter().chain(ing) {
                put(&mut out, x);
            }
        }
        out
    }

    /// Reads [`Kitchen::to_bytes`]. Anything else (truncated, corrupt, another version) is
    /// an error, never a panic: every index is checked, the kitchen is rebuilt item by item
    /// and its fingerprint must be the one recorded.
    pub fn from_bytes(data: &[u8]) -> Result<Self> {
        let mut r = Reader::new(data, bytes_error);
        if r.take(8)? != MAGIC {
            return Err(bytes_error("wrong magic or version"));
        }
        let mut fp = [0u8; 16];
        fp.copy_from_slice(r.take(16)?);
        let n = r.count()?;
        let lens = (0..n).map(|_| r.u32()).collect::<Result<Vec<u32>>>()?;
        let mut strs = Vec::with_capacity(n);
        for len in lens {
            let b = r.take(len as usize)?;
            strs.push(std::str::from_utf8(b).map_err(|_| bytes_error("invalid UTF-8"))?);
        }
        let text = |id: u32| {
            strs.get(id as usize)
                .copied()
                .ok_or_else(|| bytes_error("a string index is out of range"))
        };
        let items = r.count()?;
        let mut k = Self::new();
        let mut ids = Vec::new();
        for _ in 0..items {
            let label = text(r.u32()?)?;
            let container = match r.u32()? {
                NONE => None,
                c => Some(text(c)?),
            };
            let (ns, ni) = (r.count()?, r.count()?);
            ids.clear();
            for _ in 0..ns + ni {
                ids.push(text(r.u32()?)?);
            }
            if !k.push(
                label,
                ids[..ns].iter().copied(),
                ids[ns..].iter().copied(),
                container,
            ) {
                return Err(bytes_error("an item repeats"));
            }
        }
        if !r.rest.is_empty() {
            return Err(bytes_error("trailing bytes"));
        }
        let k = k.finish()?;
        if k.fingerprint() != u128::from_le_bytes(fp) {
            return Err(bytes_error("the fingerprint does not match the items"));
        }
        Ok(k)
    }
}

impl Default for Kitchen {
    fn default() -> Self {
        Self::new()
    }
}

/// Two kitchens are equal when they have the same set of identities (in any order).
impl PartialEq for Kitchen {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len()
            && self.fingerprint() == other.fingerprint()
            && (0..self.len()).all(|i| self.item_in(i, other))
    }
}

impl Eq for Kitchen {}

/// The fingerprint hash: two 64-bit lanes with fixed seeds, fed little-endian words, each
/// step a multiply and a rotation, finished with the `splitmix64` mixer. Fixed-width and
/// platform-independent (no `usize`, no per-process seed).
struct Fp(u64, u64);

const SEEDS: [u64; 2] = [0x9E37_79B9_7F4A_7C15, 0xC2B2_AE3D_27D4_EB4F];
const MULS: [u64; 2] = [0xFF51_AFD7_ED55_8CCD, 0xC4CE_B9FE_1A85_EC53];

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl Fp {
    fn new() -> Self {
        Self(SEEDS[0], SEEDS[1])
    }

    fn u64(&mut self, w: u64) {
        self.0 = (self.0 ^ w).wrapping_mul(MULS[0]).rotate_left(29);
        self.1 = (self.1 ^ w.rotate_left(32))
            .wrapping_mul(MULS[1])
            .rotate_left(31);
    }

    fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        let mut chunks = s.as_bytes().chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.u64(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.u64(u64::from_le_bytes(w));
        }
    }

    fn finish(&self) -> u128 {
        let a = mix(self.0 ^ mix(self.1));
        let b = mix(self.1 ^ a);
        (u128::from(a) << 64) | u128::from(b)
    }
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use proptest::prelude::*;

    use super::Kitchen;
    use crate::error::InputKind;
    use crate::model::ObjectSpec;
    use crate::parse::{ParseOptions, load_foon, load_objects, parse_objects};

    fn spec(
        label: &str,
        states: &[&str],
        ingredients: &[&str],
        container: Option<&str>,
    ) -> ObjectSpec {
        let own = |v: &[&str]| v.iter().map(|s| (*s).to_owned()).collect();
        ObjectSpec {
            label: label.to_owned(),
            states: own(states),
            ingredients: own(ingredients),
            container: container.map(str::to_owned),
        }
    }

    /// The list semantics: the specs in order, a repeated identity kept at its first place.
    fn distinct(specs: &[ObjectSpec]) -> Vec<ObjectSpec> {
        let mut out: Vec<ObjectSpec> = Vec::new();
        for s in specs {
            if !out.contains(s) {
                out.push(s.clone());
            }
        }
        out
    }

    /// The written fields of each spec (a spec's own `==` compares identities).
    type Written = (String, Vec<String>, Vec<String>, Option<String>);

    fn written(specs: &[ObjectSpec]) -> Vec<Written> {
        specs
            .iter()
            .map(|s| {
                (
                    s.label.clone(),
                    s.states.clone(),
                    s.ingredients.clone(),
                    s.container.clone(),
                )
            })
            .collect()
    }

    #[test]
    fn repeats_count_once_and_keep_the_first_form() {
        let text = "O\tonion\nS\tchopped\nS\tin\t[bowl]\nS\tred\n//\nO\tonion\nS\tred\nS\tchopped\n\
                    S\tin\t[bowl]\n//\nO\tsalt\n";
        let k = Kitchen::parse(text.as_bytes(), None).unwrap();
        assert_eq!(k.len(), 2);
        assert_eq!(k.get(0).unwrap().states, ["chopped", "red"]);
        assert_eq!(k.container(0), Some("bowl"));
        assert!(k.contains(&spec("onion", &["red", "chopped"], &[], Some("bowl"))));
        assert!(!k.contains(&spec("onion", &["red", "chopped"], &[], None)));
        assert!(!k.contains(&spec("onion", &["red"], &[], Some("bowl"))));
        assert!(!k.contains(&spec("pepper", &[], &[], None)));
        assert_eq!(k.get(2), None);
    }

    #[test]
    fn errors_are_those_of_the_list_parser() {
        for bad in [
            &b"O\tonion\nM\tchop\n"[..],
            b"S\tred\n",
            b"[{\"label\": \"x\", \"states\": [\"\"]}]",
            b"[{\"label\": 1}]",
            b"{\"label\": \"x\"}",
            b"[{\"label\": \"x\"}] x",
            b"[[\"ice\"]]",
        ] {
            let p = Some(Path::new("k.json"));
            let ours = Kitchen::parse(bad, p).unwrap_err().to_string();
            let old = parse_objects(bad, p, InputKind::Kitchen)
                .unwrap_err()
                .to_string();
            assert_eq!(ours, old);
            assert!(ours.starts_with("k.json:"), "{ours}");
        }
    }

    #[test]
    fn with_without_and_equality() {
        let a = spec("a", &["x", "y"], &[], None);
        let b = spec("b", &[], &["i", "j"], Some("pot"));
        let c = spec("c", &[], &[], Some(""));
        let k = Kitchen::from_specs([&a, &b]).unwrap();
        let k2 = Kitchen::from_specs([&spec("b", &[], &["j", "i"], Some("pot")), &a, &a]).unwrap();
        assert_eq!(k, k2);
        assert_eq!(k.fingerprint(), k2.fingerprint());
        let kc = k.with(&Kitchen::from_specs([&c, &a]).unwrap()).unwrap();
        assert_eq!(kc.specs(), [a.clone(), b.clone(), c.clone()]);
        assert_ne!(kc, k);
        assert_ne!(kc.fingerprint(), k.fingerprint());
        let back = kc.without(&Kitchen::from_specs([&c]).unwrap());
        assert_eq!(back, k);
        assert_eq!(back.fingerprint(), k.fingerprint());
        assert!(kc.without(&kc).is_empty());
        assert_eq!(
            Kitchen::new().fingerprint(),
            Kitchen::default().fingerprint()
        );
        // A container "" is not no container; one state is not its repetition.
        assert_ne!(
            Kitchen::from_specs([&spec("c", &[], &[], None)]).unwrap(),
            Kitchen::from_specs([&c]).unwrap()
        );
        assert_ne!(
            Kitchen::from_specs([&spec("s", &["x"], &[], None)])
                .unwrap()
                .fingerprint(),
            Kitchen::from_specs([&spec("s", &["x", "x"], &[], None)])
                .unwrap()
                .fingerprint()
        );
    }

    #[test]
    fn fingerprint_is_fixed() {
        // The fingerprint is part of cache keys across machines: a change is a format change.
        let k = Kitchen::from_specs([&spec("onion", &["chopped"], &["a"], Some("bowl"))]).unwrap();
        assert_eq!(
            k.fingerprint(),
            Kitchen::from_specs(&k.specs()).unwrap().fingerprint()
        );
        assert_eq!(
            format!("{:032x}", Kitchen::new().fingerprint()),
            format!("{:032x}", Kitchen::from_specs([]).unwrap().fingerprint())
        );
    }

    #[test]
    fn bytes_round_trip_and_refuse_corruption() {
        let k = Kitchen::from_specs(&[
            spec("onion", &["chopped", "red"], &["a", ""], Some("bowl")),
            spec("é", &[], &[], Some("")),
            spec("salt", &[], &[], None),
        ])
        .unwrap();
        let b = k.to_bytes();
        let back = Kitchen::from_bytes(&b).unwrap();
        assert_eq!(written(&back.specs()), written(&k.specs()));
        assert_eq!(back.fingerprint(), k.fingerprint());
        assert!(
            Kitchen::from_bytes(&Kitchen::new().to_bytes())
                .unwrap()
                .is_empty()
        );
        // Every truncation and every flipped byte is an error or the same kitchen, never a
        // panic (a flipped byte in a string's text changes the fingerprint).
        for n in 0..b.len() {
            assert!(Kitchen::from_bytes(&b[..n]).is_err());
            for bit in [0x01u8, 0x80] {
                let mut c = b.clone();
                c[n] ^= bit;
                if let Ok(x) = Kitchen::from_bytes(&c) {
                    assert_eq!(x, k);
                }
            }
        }
        let mut long = b.clone();
        long.push(0);
        let e = Kitchen::from_bytes(&long).unwrap_err().to_string();
        assert!(e.contains("not a valid serialised kitchen"), "{e}");
    }

    fn shared() -> Option<PathBuf> {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/foon");
        if p.join("FOON.txt").is_file() {
            return Some(p);
        }
        assert!(
            std::env::var_os("FOON_REQUIRE_DATA").is_none(),
            "FOON_REQUIRE_DATA is set but ../shared/data/foon is missing"
        );
        eprintln!("skipped: ../shared/data/foon (the real FOON data) is not beside the repository");
        None
    }

    #[test]
    fn real_kitchens_match_as_lists_do() {
        let Some(dir) = shared() else { return };
        let foon = load_foon(&dir.join("FOON.txt"), ParseOptions::default()).unwrap();
        let mut files = vec![dir.join("kitchen.json")];
        for e in std::fs::read_dir(dir.join("lab_history")).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            if name.starts_with("kitchen") {
                files.push(p);
            }
        }
        assert!(files.len() > 5);
        for f in &files {
            let list = load_objects(f, InputKind::Kitchen).unwrap();
            let k = Kitchen::load(f).unwrap();
            assert_eq!(
                written(&k.specs()),
                written(&distinct(&list)),
                "{}",
                f.display()
            );
            assert!(list.iter().all(|s| k.contains(s)));
            let mut ids: Vec<u32> = list.iter().filter_map(|s| s.find_in(&foon)).collect();
            ids.sort_unstable();
            ids.dedup();
            assert_eq!(k.match_in(&foon), ids, "{}", f.display());
        }
        assert_eq!(
            Kitchen::load(&dir.join("kitchen.json")).unwrap().len(),
            1174
        );
        // Many kitchens matched at once (the memo of shared items and strings) against each
        // kitchen's items looked up one by one (level 3) or by their level keys as text.
        let lists: Vec<Vec<ObjectSpec>> = files
            .iter()
            .map(|f| load_objects(f, InputKind::Kitchen).unwrap())
            .collect();
        let kitchens: Vec<Kitchen> = files.iter().map(|f| Kitchen::load(f).unwrap()).collect();
        let refs: Vec<&Kitchen> = kitchens.iter().chain(&kitchens).collect();
        let key = |level: u8, label: &str, container: Option<&str>, states: &[String]| {
            let mut st: Vec<String> = states.to_vec();
            st.sort_unstable();
            match level {
                1 => (label.to_owned(), None, Vec::new()),
                _ => (label.to_owned(), container.map(str::to_owned), st),
            }
        };
        for level in [1u8, 2, 3] {
            let many = Kitchen::match_many(&refs, &foon, level).unwrap();
            assert_eq!(many.len(), 2 * files.len());
            for (i, list) in lists.iter().chain(&lists).enumerate() {
                let want: Vec<u32> = if level == 3 {
                    let mut ids: Vec<u32> = list.iter().filter_map(|s| s.find_in(&foon)).collect();
                    ids.sort_unstable();
                    ids.dedup();
                    ids
                } else {
                    let keys: std::collections::HashSet<_> = list
                        .iter()
                        .map(|s| key(level, &s.label, s.container.as_deref(), &s.states))
                        .collect();
                    (0..foon.object_count() as u32)
                        .filter(|&o| {
                            let sp = ObjectSpec::of_object(&foon, o);
                            keys.contains(&key(
                                level,
                                &sp.label,
                                sp.container.as_deref(),
                                &sp.states,
                            ))
                        })
                        .collect()
                };
                assert_eq!(many[i], want, "level {level}, kitchen {i}");
                assert_eq!(refs[i].match_at_level(&foon, level).unwrap(), want);
            }
        }
        assert!(Kitchen::match_many(&refs, &foon, 4).is_err());
    }

    fn specs() -> impl Strategy<Value = Vec<ObjectSpec>> {
        let word = prop::sample::select(vec!["a", "b", "c", "é", "a b", "", "dd"]);
        let item = (
            prop::sample::select(vec!["x", "y", "z"]),
            prop::collection::vec(word.clone().prop_filter("state", |s| !s.is_empty()), 0..3),
            prop::collection::vec(word.clone(), 0..3),
            prop::option::of(word),
        )
            .prop_map(|(l, s, i, c)| spec(l, &s, &i, c));
        prop::collection::vec(item, 0..24)
    }

    proptest! {
        #[test]
        fn behaves_as_the_list(list in specs(), other in specs(), seed in any::<u64>()) {
            let k = Kitchen::from_specs(&list).unwrap();
            let want = distinct(&list);
            prop_assert_eq!(written(&k.specs()), written(&want));
            for s in list.iter().chain(&other) {
                prop_assert_eq!(k.contains(s), want.contains(s));
            }
            // The same set in another order, with repeats: equal, same fingerprint.
            let mut shuffled = list.clone();
            shuffled.extend(list.iter().take(3).cloned());
            let n = shuffled.len();
            for i in 0..n {
                let j = (seed as usize).wrapping_mul(i + 7) % n;
                shuffled.swap(i, j);
            }
            let ks = Kitchen::from_specs(&shuffled).unwrap();
            prop_assert!(ks == k);
            prop_assert_eq!(ks.fingerprint(), k.fingerprint());
            let o = Kitchen::from_specs(&other).unwrap();
            let same = distinct(&other).len() == want.len() && want.iter().all(|s| other.contains(s));
            prop_assert_eq!(o == k, same);
            if !same {
                prop_assert_ne!(o.fingerprint(), k.fingerprint());
            }
            let gone: Vec<ObjectSpec> = want.iter().filter(|s| !other.contains(s)).cloned().collect();
            prop_assert_eq!(written(&k.without(&o).specs()), written(&gone));
            let mut both = want.clone();
            both.extend(distinct(&other).into_iter().filter(|s| !want.contains(s)));
            prop_assert_eq!(written(&k.with(&o).unwrap().specs()), written(&both));
            prop_assert!(Kitchen::from_bytes(&k.to_bytes()).unwrap() == k);
            // Text round trip through the JSON form.
            let json = crate::write::json::objects_json(&k.specs()).unwrap();
            prop_assert!(Kitchen::parse(json.as_bytes(), None).unwrap() == k);
        }

        /// A chain of changes applied at once is the kitchen of its steps applied one by one:
        /// the same items in the same order and forms (an item removed and added again
        /// comes back last, in the form it is added in).
        #[test]
        fn chains_of_changes_are_their_steps(
            base in specs(),
            steps in prop::collection::vec(
                (
                    specs(),
                    specs(),
                    prop::collection::vec(any::<prop::sample::Index>(), 0..6),
                    prop::collection::vec(any::<prop::sample::Index>(), 0..6),
                ),
                0..6,
            ),
        ) {
            let k = Kitchen::from_specs(&base).unwrap();
            // Steps that also remove items of the base and add them back in another form
            // (states and ingredients in reverse order: the same identity).
            let pick = |at: &[prop::sample::Index], reverse: bool| -> Vec<ObjectSpec> {
                if base.is_empty() {
                    return Vec::new();
                }
                at.iter()
                    .map(|i| {
                        let mut s = base[i.index(base.len())].clone();
                        if reverse {
                            s.states.reverse();
                            s.ingredients.reverse();
                        }
                        s
                    })
                    .collect()
            };
            let kitchens: Vec<(Kitchen, Kitchen)> = steps
                .iter()
                .map(|(a, r, again, gone)| {
                    let (mut a, mut r) = (a.clone(), r.clone());
                    a.extend(pick(again, true));
                    r.extend(pick(gone, false));
                    (Kitchen::from_specs(&a).unwrap(), Kitchen::from_specs(&r).unwrap())
                })
                .collect();
            let mut one_by_one = k.clone();
            for (a, r) in &kitchens {
                one_by_one = one_by_one.without(r).with(a).unwrap();
            }
            let refs: Vec<(&Kitchen, &Kitchen)> = kitchens.iter().map(|(a, r)| (a, r)).collect();
            let at_once = k.with_steps(&refs).unwrap();
            prop_assert_eq!(written(&at_once.specs()), written(&one_by_one.specs()));
            prop_assert!(at_once == one_by_one);
            prop_assert_eq!(at_once.fingerprint(), one_by_one.fingerprint());
        }

        /// The fingerprint of a kitchen changed by a delta, from the base's, is the changed
        /// kitchen's (items removed and added again, added and already there, removed and
        /// absent).
        #[test]
        fn delta_fingerprints_are_the_kitchens(base in specs(), add in specs(), remove in specs()) {
            let (k, a, r) = (
                Kitchen::from_specs(&base).unwrap(),
                Kitchen::from_specs(&add).unwrap(),
                Kitchen::from_specs(&remove).unwrap(),
            );
            let built = k.without(&r).with(&a).unwrap();
            prop_assert_eq!(k.fingerprint_with_changes(&a, &r), built.fingerprint());
            // Without computing the base's first, and with the delta's items in the base.
            let (k2, r2) = (Kitchen::from_specs(&base).unwrap(), k.without(&a));
            let built2 = k2.without(&r2).with(&a).unwrap();
            prop_assert_eq!(k2.fingerprint_with_changes(&a, &r2), built2.fingerprint());
        }
    }
}

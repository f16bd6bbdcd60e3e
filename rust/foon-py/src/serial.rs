//! The stable serialised form of a parsed FOON, for pickling: its string table, its units with
//! every object occurrence as written (so unit indices, object ids, lines and written orders
//! come back as they were), the duplicates it dropped, and its warnings and notes. Rebuilt
//! through the core's index builder, so every derived column is computed as on a load.

use std::path::PathBuf;

use foon_core::index::{Builder, RawObject};
use foon_core::{Foon, Location, NONE, Warning, WarningKind};

const MAGIC: &[u8] = b"FOON-INDEX\x01";

/// Every warning kind, by its code in the serialised form (the index in this list).
const KINDS: [WarningKind; 9] = [
    WarningKind::NoMotion,
    WarningKind::TwoMotions,
    WarningKind::Unterminated,
    WarningKind::SpacedIngredient,
    WarningKind::DuplicateIngredient,
    WarningKind::EmptyContainer,
    WarningKind::TwoContainers,
    WarningKind::TwoIngredientLists,
    WarningKind::EmptyIngredient,
];

fn kind_code(k: WarningKind) -> u8 {
    // Exhaustive: a new kind does not compile until it has a code here and in KINDS.
    match k {
        WarningKind::NoMotion => 0,
        WarningKind::TwoMotions => 1,
        WarningKind::Unterminated => 2,
        WarningKind::SpacedIngredient => 3,
        WarningKind::DuplicateIngredient => 4,
        WarningKind::EmptyContainer => 5,
        WarningKind::TwoContainers => 6,
        WarningKind::TwoIngredientLists => 7,
        WarningKind::EmptyIngredient => 8,
    }
}

struct Out(Vec<u8>);

impl Out {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn len(&mut self, n: usize) {
        self.u32(n as u32);
    }
    fn str(&mut self, s: &str) {
        self.len(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    fn opt_str(&mut self, s: Option<&str>) {
        match s {
            Some(s) => {
                self.u8(1);
                self.str(s);
            }
            None => self.u8(0),
        }
    }
    fn ids(&mut self, ids: &[u32]) {
        self.len(ids.len());
        for &i in ids {
            self.u32(i);
        }
    }
}

/// Serialises `foon` (see the module documentation).
pub(crate) fn encode(foon: &Foon) -> Vec<u8> {
    let mut o = Out(Vec::with_capacity(64 + foon.fu_count() * 64));
    o.0.extend_from_slice(MAGIC);
    let source = foon.source().map(|p| p.to_string_lossy().into_owned());
    o.opt_str(source.as_deref());
    let strings = foon.strings();
    o.len(strings.len());
    for id in 0..strings.len() as u32 {
        o.str(strings.text(id));
    }
    o.len(foon.fu_count());
    for f in 0..foon.fu_count() as u32 {
        o.u32(foon.motion(f));
        let meta = foon
            .motion_meta(f)
            .and_then(|m| strings.get(m))
            .unwrap_or(NONE);
        o.u32(meta);
        o.u32(foon.fu_line(f));
        for (vars, in_motion) in [
            (foon.input_variants(f), foon.input_in_motion(f)),
            (foon.output_variants(f), foon.output_in_motion(f)),
        ] {
            o.len(vars.len());
            for (k, &v) in vars.iter().enumerate() {
                let obj = foon.variant_object(v);
                o.u32(foon.label(obj));
                o.u32(foon.container(obj));
                o.u8(in_motion.get(k).copied().unwrap_or(0));
                o.ids(foon.variant_states(v));
                o.ids(foon.variant_ingredients(v));
            }
        }
    }
    o.len(foon.duplicates().len());
    for d in foon.duplicates() {
        o.u32(d.line);
        o.u32(d.of);
    }
    for list in [foon.warnings(), foon.notes()] {
        o.len(list.len());
        for w in list {
            let path = w.at.path.as_ref().map(|p| p.to_string_lossy().into_owned());
            o.opt_str(path.as_deref());
            o.u64(w.at.line);
            o.u32(w.at.column);
            o.u8(kind_code(w.kind));
            o.str(&w.message);
        }
    }
    o.0
}

struct In<'a> {
    data: &'a [u8],
}

type Res<T> = Result<T, String>;

impl<'a> In<'a> {
    fn take(&mut self, n: usize) -> Res<&'a [u8]> {
        if self.data.len() < n {
            return Err("the data ends too early".into());
        }
        let (a, b) = self.data.split_at(n);
        self.data = b;
        Ok(a)
    }
    fn u8(&mut self) -> Res<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Res<u32> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().unwrap_or_default(),
        ))
    }
    fn u64(&mut self) -> Res<u64> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().unwrap_or_default(),
        ))
    }
    fn len(&mut self) -> Res<usize> {
        let n = self.u32()? as usize;
        // Every element takes at least one byte: a longer count is corrupt data.
        if n > self.data.len() {
            return Err("a count is larger than the data".into());
        }
        Ok(n)
    }
    fn str(&mut self) -> Res<&'a str> {
        let n = self.len()?;
        std::str::from_utf8(self.take(n)?).map_err(|_| "a string is not UTF-8".to_owned())
    }
    fn opt_str(&mut self) -> Res<Option<&'a str>> {
        match self.u8()? {
            0 => Ok(None),
            1 => self.str().map(Some),
            _ => Err("bad optional string".into()),
        }
    }
    fn ids(&mut self) -> Res<Vec<u32>> {
        let n = self.len()?;
        (0..n).map(|_| self.u32()).collect()
    }
}

/// One object occurrence as written.
struct Occurrence {
    label: u32,
    container: u32,
    in_motion: u8,
    states: Vec<u32>,
    ingredients: Vec<u32>,
}

impl Occurrence {
    fn raw(&self) -> RawObject<'_> {
        RawObject {
            label: self.label,
            states: &self.states,
            ingredients: &self.ingredients,
            container: self.container,
            in_motion: self.in_motion,
        }
    }
}

struct Unit {
    motion: u32,
    meta: u32,
    line: u32,
    inputs: Vec<Occurrence>,
    outputs: Vec<Occurrence>,
}

impl Unit {
    fn add_to(&self, b: &mut Builder, line: u32) -> Result<u32, u32> {
        let ins: Vec<RawObject<'_>> = self.inputs.iter().map(Occurrence::raw).collect();
        let outs: Vec<RawObject<'_>> = self.outputs.iter().map(Occurrence::raw).collect();
        b.add_fu(self.motion, self.meta, &ins, &outs, line)
    }
}

/// Rebuilds a FOON from [`encode`]'s output.
pub(crate) fn decode(data: &[u8]) -> Res<Foon> {
    let mut r = In { data };
    if r.take(MAGIC.len())? != MAGIC {
        return Err("not a serialised FOON of this version".into());
    }
    let source = r.opt_str()?.map(PathBuf::from);
    let mut b = Builder::new();
    b.begin_source(source.as_deref());
    let n_strings = r.len()?;
    for id in 0..n_strings as u32 {
        let s = r.str()?;
        if b.intern(s) != id {
            return Err("the string table repeats a string".into());
        }
    }
    let check = |id: u32| -> Res<u32> {
        if id == NONE || (id as usize) < n_strings {
            Ok(id)
        } else {
            Err("a string id is out of range".into())
        }
    };
    let n_fu = r.len()?;
    let mut units = Vec::with_capacity(n_fu);
    for _ in 0..n_fu {
        let motion = check(r.u32()?)?;
        let meta = check(r.u32()?)?;
        let line = r.u32()?;
        let mut sides = [Vec::new(), Vec::new()];
        for side in &mut sides {
            let n = r.len()?;
            for _ in 0..n {
                let label = check(r.u32()?)?;
                let container = check(r.u32()?)?;
                let in_motion = r.u8()?;
                let states = r.ids()?;
                let ingredients = r.ids()?;
                for &s in states.iter().chain(&ingredients) {
                    check(s)?;
                }
                side.push(Occurrence {
                    label,
                    container,
                    in_motion,
                    states,
                    ingredients,
                });
            }
        }
        let [inputs, outputs] = sides;
        units.push(Unit {
            motion,
            meta,
            line,
            inputs,
            outputs,
        });
    }
    for (i, u) in units.iter().enumerate() {
        if u.add_to(&mut b, u.line) != Ok(i as u32) {
            return Err("two units are the same".into());
        }
    }
    // Duplicates come after every kept unit: they only add to the list of dropped copies.
    let n_dup = r.len()?;
    for _ in 0..n_dup {
        let line = r.u32()?;
        let of = r.u32()?;
        let u = units
            .get(of as usize)
            .ok_or("a duplicate of an unknown unit")?;
        if u.add_to(&mut b, line) != Err(of) {
            return Err("a duplicate is not a copy".into());
        }
    }
    for notes in [false, true] {
        let n = r.len()?;
        for _ in 0..n {
            let path = r.opt_str()?.map(PathBuf::from);
            let line = r.u64()?;
            let column = r.u32()?;
            let kind = *KINDS
                .get(r.u8()? as usize)
                .ok_or("an unknown warning kind")?;
            let message = r.str()?.to_owned();
            let w = Warning {
                at: Location { path, line, column },
                kind,
                message,
            };
            if notes {
                b.note(w);
            } else {
                b.warn(w);
            }
        }
    }
    if !r.data.is_empty() {
        return Err("data after the end".into());
    }
    Ok(b.finish())
}

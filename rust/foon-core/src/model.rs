//! The domain model: an object given by its text fields ([`ObjectSpec`]), the one definition
//! of object identity, motion success rates ([`MotionRates`]) and the one range check of a
//! rate ([`check_rate`]).

use std::hash::{Hash, Hasher};

use rustc_hash::FxHashMap;

use crate::error::{Error, Result};
use crate::index::{Foon, NONE};

/// The canonical form of an object's multisets, the one definition of object identity
/// (SEMANTICS §2: label, container, and the states and the ingredients as sorted multisets).
/// Writes the states, sorted, then the ingredients, sorted, into `key` and returns the number
/// of states. The index applies it to string ids, [`ObjectSpec`] to text.
pub(crate) fn canonical_into<T: Ord + Copy>(
    states: &[T],
    ingredients: &[T],
    key: &mut Vec<T>,
) -> usize {
    key.clear();
    key.extend_from_slice(states);
    key.sort_unstable();
    let ns = key.len();
    key.extend_from_slice(ingredients);
    key[ns..].sort_unstable();
    ns
}

/// Checks a success rate: a number between 0 and 1 (NaN is not). `motion` names the motion
/// in the message (`None` for a default rate). The one range check of rates.
pub fn check_rate(motion: Option<&str>, r: f64) -> Result<f64> {
    if (0.0..=1.0).contains(&r) {
        return Ok(r);
    }
    Err(Error::Invalid(match motion {
        Some(m) => format!("the rate of '{m}' is {r}, not between 0 and 1"),
        None => format!("the default rate is {r}, not between 0 and 1"),
    }))
}

/// An object given by its text fields (a kitchen item or a goal).
///
/// Two specs are equal (and hash alike) when they have the same identity: the same label and
/// container, and the same states and ingredients as multisets (in any order).
#[derive(Debug, Clone, Default)]
pub struct ObjectSpec {
    pub label: String,
    pub states: Vec<String>,
    pub ingredients: Vec<String>,
    pub container: Option<String>,
}
/// Why a label is not valid, if it is not.
pub(crate) fn label_fault(label: &str) -> Option<&'static str> {
    label
        .trim()
        .is_empty()
        .then_some("an object has an empty label")
}

/// Why a list of states is not valid, if it is not.
pub(crate) fn states_fault(states: &[String]) -> Option<&'static str> {
    states
        .iter()
        .any(|s| s.trim().is_empty())
        .then_some("an object has an empty state")
}

impl ObjectSpec {
    /// A checked spec: the one place that validates one. The label must not be empty (nor
    /// only spaces), nor may any state. Ingredients may be empty strings (the course reads
    /// `{}` as one ingredient `''`), and the container may be `Some("")` (`[]`).
    pub fn new(
        label: impl Into<String>,
        states: Vec<String>,
        ingredients: Vec<String>,
        container: Option<String>,
    ) -> Result<Self> {
        let label = label.into();
        if let Some(f) = label_fault(&label).or_else(|| states_fault(&states)) {
            return Err(Error::Invalid(f.to_owned()));
        }
        Ok(Self {
            label,
            states,
            ingredients,
            container,
        })
    }

    /// The identity: label, sorted states, sorted ingredients, container.
    pub fn identity(&self) -> (&str, Vec<&str>, Vec<&str>, Option<&str>) {
        let s: Vec<&str> = self.states.iter().map(String::as_str).collect();
        let i: Vec<&str> = self.ingredients.iter().map(String::as_str).collect();
        let mut key = Vec::with_capacity(s.len() + i.len());
        let ns = canonical_into(&s, &i, &mut key);
        let ingredients = key.split_off(ns);
        (&self.label, key, ingredients, self.container.as_deref())
    }

    /// The object of `foon` with this identity.
    pub fn find_in(&self, foon: &Foon) -> Option<u32> {
        let s: Vec<&str> = self.states.iter().map(String::as_str).collect();
        let i: Vec<&str> = self.ingredients.iter().map(String::as_str).collect();
        foon.find_object(&self.label, &s, &i, self.container.as_deref())
    }

    /// A one-line description: `label (s1, s2) {ingredients} in [container]`.
    pub fn describe(&self) -> String {
        use std::fmt::Write as _;
        let mut s = self.label.clone();
        if !self.states.is_empty() {
            let _ = write!(s, " ({})", self.states.join(", "));
        }
        if !self.ingredients.is_empty() {
            let _ = write!(s, " {{{}}}", self.ingredients.join(","));
        }
        if let Some(c) = &self.container {
            let _ = write!(s, " in [{c}]");
        }
        s
    }

    /// The object `obj` of `foon` as a spec, in its first written form.
    pub fn of_object(foon: &Foon, obj: u32) -> Self {
        let v = foon.first_variant(obj);
        let c = foon.container(obj);
        Self {
            label: foon.label_text(obj).to_owned(),
            states: foon
                .variant_states(v)
                .iter()
                .map(|&s| foon.text(s).to_owned())
                .collect(),
            ingredients: foon
                .variant_ingredients(v)
                .iter()
                .map(|&s| foon.text(s).to_owned())
                .collect(),
            container: (c != NONE).then(|| foon.text(c).to_owned()),
        }
    }
}

impl PartialEq for ObjectSpec {
    fn eq(&self, other: &Self) -> bool {
        self.identity() == other.identity()
    }
}

impl Eq for ObjectSpec {}

impl Hash for ObjectSpec {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.identity().hash(state);
    }
}

/// Motion success rates: `motion<TAB>rate` lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MotionRates {
    /// In file order, each motion once.
    pub entries: Vec<(String, f64)>,
    /// Position of each motion in `entries`.
    map: FxHashMap<String, usize>,
}

impl MotionRates {
    /// Rates from `(motion, rate)` pairs. Every rate is checked ([`check_rate`]); the same
    /// motion twice with the same rate is kept once, with two different rates it is an error.
    /// A table from (motion, rate) pairs. Motion names follow the rate file's rule
    /// ([`MotionRates::motion_name`]), so a table built in code matches the FOON's motions
    /// exactly as one read from a file does.
    pub fn from_pairs(pairs: impl IntoIterator<Item = (String, f64)>) -> Result<Self> {
        let mut r = Self::default();
        for (m, v) in pairs {
            let m = Self::motion_name(&m);
            if m.is_empty() {
                return Err(Error::Invalid("empty motion name".into()));
            }
            check_rate(Some(&m), v)?;
            if let Err(old) = r.insert(m, v) {
                let (m, first) = &r.entries[old];
                return Err(Error::Invalid(format!(
                    "motion '{m}' has two rates: {first} and {v}"
                )));
            }
        }
        Ok(r)
    }

    /// A motion name as rate tables key it: trimmed and lower-cased (the FOON's motion lines
    /// are lower-cased and right-stripped, so every motion of a FOON matches its entry).
    pub fn motion_name(name: &str) -> String {
        name.trim().to_lowercase()
    }

    /// Adds a rate; a motion already given with another rate is left as it is and the
    /// position of its entry is returned.
    // The same number written twice is the same rate: exact equality is meant.
    #[allow(clippy::float_cmp)]
    pub(crate) fn insert(&mut self, m: String, v: f64) -> std::result::Result<(), usize> {
        if let Some(&i) = self.map.get(&m) {
            return if self.entries[i].1 == v {
                Ok(())
            } else {
                Err(i)
            };
        }
        self.map.insert(m.clone(), self.entries.len());
        self.entries.push((m, v));
        Ok(())
    }

    pub fn get(&self, motion: &str) -> Option<f64> {
        self.map.get(motion).map(|&i| self.entries[i].1)
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

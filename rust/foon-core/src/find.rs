//! `foon find`: objects ranked by the similarity of their label, states and container to a
//! free-text query such as `chopped onion in bowl`.
//!
//! The similarity of two strings is `strsim`'s Jaro-Winkler similarity of their lowercase
//! forms. A query is cut at its last ` in ` into a main part and a container (brackets
//! dropped); the main part is a list of words. For an object with label `l`, states `S` and
//! container `c`:
//!
//! - **label**: the best similarity of `l` to a run of consecutive words of the main part
//!   (the run is then used up);
//! - **states**: the larger of (each remaining word's best similarity to a state of `S`,
//!   summed and divided by the larger of the number of remaining words and `|S|`) and the
//!   similarity of the remaining words to the states, each joined with spaces in order (for
//!   states of several words, `over sink`); 1 when both are empty;
//! - **container**: the similarity of the query's container to `c` (0 when the object has
//!   none); without a container in the query, 1 for an object without one and 0.5 for one
//!   with one;
//! - **score** = 0.6 label + 0.25 states + 0.15 container; ties by object id.
//!
//! Only objects whose label is among the [`LABELS`] best labels are scored (labels in
//! decreasing label score, stopping once no object of the next label can enter the k best). The labels
//! compared are those sharing a trigram with a word of the query (every label when the query
//! has no trigram), found in trigram postings over the distinct labels ([`FindIndex`], built
//! once per FOON): a query costs the labels it touches plus the objects of the best labels,
//! not the size of the FOON.

use rustc_hash::FxHashMap;

use crate::error::Error;
use crate::index::{Foon, NONE};
use crate::model::ObjectSpec;

/// How many of the best-matching labels have their objects scored.
pub const LABELS: usize = 16;

/// How many labels (those sharing the most trigrams with the query) are compared.
pub const CANDIDATES: usize = 512;

/// How many objects a "goal not found" error suggests.
pub const SUGGESTED: usize = 3;

/// [`Error::GoalNotFound`] for a goal (`described` as the message names it) that is not in
/// `foon`, with the [`SUGGESTED`] objects most similar to it, described, best first: the
/// objects [`FindIndex::find`] ranks first for the goal's states, label and container (`foon
/// find` with the query `states label in container`; a goal given by label has only its
/// label). Every "not found" goal given by its fields goes through here, so its message is
/// always built the same way.
pub fn goal_not_found(
    foon: &Foon,
    described: String,
    label: &str,
    states: &[String],
    container: Option<&str>,
) -> Error {
    let mut query = states.join(" ");
    if !query.is_empty() {
        query.push(' ');
    }
    query.push_str(label);
    if let Some(c) = container {
        query.push_str(" in ");
        query.push_str(c);
    }
    let nearest = foon
        .find_index()
        .find(foon, &query, SUGGESTED)
        .iter()
        .map(|f| ObjectSpec::of_object(foon, f.object).describe())
        .collect();
    Error::GoalNotFound {
        goal: described,
        nearest,
    }
}

/// The candidate index of a FOON: its distinct labels (lowercase), trigram postings over
/// them, and the objects of each label.
#[derive(Debug, Clone, Default)]
pub struct FindIndex {
    labels: Vec<String>,
    /// Objects of label `i`: `objects[starts[i]..starts[i + 1]]`, in id order.
    starts: Vec<u32>,
    objects: Vec<u32>,
    trigrams: FxHashMap<[u8; 3], Vec<u32>>,
}

fn trigrams(word: &str, mut each: impl FnMut([u8; 3])) {
    let b = word.as_bytes();
    for w in b.windows(3) {
        each([w[0], w[1], w[2]]);
    }
}

fn sim(a: &str, b: &str) -> f64 {
    strsim::jaro_winkler(a, b)
}

/// One scored object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    pub object: u32,
    pub score: f64,
}

struct Query {
    words: Vec<String>,
    container: Option<String>,
}

fn parse_query(text: &str) -> Query {
    let lower = text.to_lowercase();
    let (main, container) = match lower.rfind(" in ") {
        Some(i) => {
            let c: String = lower[i + 4..]
                .chars()
                .filter(|&ch| ch != '[' && ch != ']')
                .collect();
            let c = c.trim().to_owned();
            (lower[..i].to_owned(), (!c.is_empty()).then_some(c))
        }
        None => (lower, None),
    };
    let words = main
        .split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
        .filter(|w| !w.is_empty())
        .map(str::to_owned)
        .collect();
    Query { words, container }
}

impl FindIndex {
    /// Builds the index: one pass over the objects, one over the distinct labels.
    pub fn build(foon: &Foon) -> Self {
        let mut label_of: FxHashMap<u32, u32> = FxHashMap::default();
        let mut labels = Vec::new();
        let mut per: Vec<Vec<u32>> = Vec::new();
        for o in 0..foon.object_count() as u32 {
            let l = foon.label(o);
            let i = *label_of.entry(l).or_insert_with(|| {
                labels.push(foon.text(l).to_lowercase());
                per.push(Vec::new());
                (labels.len() - 1) as u32
            });
            per[i as usize].push(o);
        }
        let mut starts = Vec::with_capacity(per.len() + 1);
        let mut objects = Vec::with_capacity(foon.object_count());
        starts.push(0);
        for p in per {
            objects.extend(p);
            starts.push(objects.len() as u32);
        }
        let mut trigrams_map: FxHashMap<[u8; 3], Vec<u32>> = FxHashMap::default();
        for (i, l) in labels.iter().enumerate() {
            trigrams(l, |t| {
                let v = trigrams_map.entry(t).or_default();
                if v.last() != Some(&(i as u32)) {
                    v.push(i as u32);
                }
            });
        }
        Self {
            labels,
            starts,
            objects,
            trigrams: trigrams_map,
        }
    }

    /// The best label score for `label` over runs of `words`, and the run `(start, len)`.
    fn label_score(label: &str, words: &[String]) -> (f64, usize, usize) {
        let mut best = (0.0, 0, 0);
        for start in 0..words.len() {
            let mut run = String::new();
            for len in 1..=words.len() - start {
                if len > 1 {
                    run.push(' ');
                }
                run.push_str(&words[start + len - 1]);
                let s = sim(&run, label);
                if s > best.0 {
                    best = (s, start, len);
                }
            }
        }
        best
    }

    /// The states and container part of the score (0.25 states + 0.15 container).
    fn rest_score(
        foon: &Foon,
        rest: &[&str],
        states: &[u32],
        c: u32,
        query_container: Option<&str>,
    ) -> f64 {
        let states: Vec<String> = states
            .iter()
            .map(|&s| foon.text(s).to_lowercase())
            .collect();
        let ss = if rest.is_empty() && states.is_empty() {
            1.0
        } else {
            let sum: f64 = rest
                .iter()
                .map(|w| states.iter().map(|s| sim(w, s)).fold(0.0, f64::max))
                .sum();
            let per_word = sum / rest.len().max(states.len()) as f64;
            per_word.max(sim(&rest.join(" "), &states.join(" ")))
        };
        let cs = match (query_container, c) {
            (None, NONE) => 1.0,
            (None, _) => 0.5,
            (Some(_), NONE) => 0.0,
            (Some(qc), c) => sim(qc, &foon.text(c).to_lowercase()),
        };
        0.25 * ss + 0.15 * cs
    }

    /// The `k` objects most similar to `text`, best first (ties by id).
    pub fn find(&self, foon: &Foon, text: &str, k: usize) -> Vec<Found> {
        let q = parse_query(text);
        if k == 0 || self.labels.is_empty() {
            return Vec::new();
        }
        // Candidate labels: the [`CANDIDATES`] sharing the most trigrams with the words (ties:
        // first label first); without a shared trigram, those sharing a pair of letters.
        let mut hits: FxHashMap<u32, u32> = FxHashMap::default();
        for w in &q.words {
            trigrams(w, |t| {
                if let Some(ls) = self.trigrams.get(&t) {
                    for &l in ls {
                        *hits.entry(l).or_default() += 1;
                    }
                }
            });
        }
        if hits.is_empty() {
            for (i, l) in self.labels.iter().enumerate() {
                let n = q
                    .words
                    .iter()
                    .flat_map(|w| w.as_bytes().windows(2))
                    .filter(|p| l.as_bytes().windows(2).any(|x| x == *p))
                    .count();
                if n > 0 {
                    hits.insert(i as u32, n as u32);
                }
            }
        }
        let mut ranked: Vec<(u32, u32)> = hits.into_iter().collect();
        ranked.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        ranked.truncate(CANDIDATES);
        let cands: Vec<u32> = ranked.into_iter().map(|(l, _)| l).collect();
        let mut scored: Vec<(f64, u32, usize, usize)> = cands
            .iter()
            .map(|&l| {
                let (s, a, n) = Self::label_score(&self.labels[l as usize], &q.words);
                (s, l, a, n)
            })
            .collect();
        scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        scored.truncate(LABELS);
        let mut found = Vec::new();
        // Objects of a label differ mostly by ingredients, which the score ignores: the
        // states and container part is computed once per (states, container).
        let mut memo: FxHashMap<(&[u32], u32), f64> = FxHashMap::default();
        // Labels in decreasing label score: an object scores at most 0.6 ls + 0.4, so once
        // that is below the k-th best score found, no later label can enter the k best.
        let by_score =
            |a: &Found, b: &Found| b.score.total_cmp(&a.score).then(a.object.cmp(&b.object));
        for &(ls, l, start, len) in &scored {
            if found.len() >= k {
                if found.len() > k {
                    found.select_nth_unstable_by(k - 1, by_score);
                    found.truncate(k);
                }
                let kth = found.iter().map(|f| f.score).fold(f64::INFINITY, f64::min);
                if 0.6 * ls + 0.4 < kth {
                    break;
                }
            }
            let rest: Vec<&str> = q
                .words
                .iter()
                .enumerate()
                .filter(|&(i, _)| len == 0 || i < start || i >= start + len)
                .map(|(_, w)| w.as_str())
                .collect();
            memo.clear();
            let (a, b) = (
                self.starts[l as usize] as usize,
                self.starts[l as usize + 1] as usize,
            );
            for &o in &self.objects[a..b] {
                let c = foon.container(o);
                let part = *memo.entry((foon.states(o), c)).or_insert_with(|| {
                    Self::rest_score(foon, &rest, foon.states(o), c, q.container.as_deref())
                });
                found.push(Found {
                    object: o,
                    score: 0.6 * ls + part,
                });
            }
        }
        if found.len() > k {
            found.select_nth_unstable_by(k - 1, by_score);
            found.truncate(k);
        }
        found.sort_by(by_score);
        found
    }
}

#[cfg(test)]
mod tests {
    use super::FindIndex;
    use crate::parse::{ParseOptions, parse_foon};

    #[test]
    fn the_closest_object_comes_first() {
        let text = "O\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\nS\tin\t[bowl]\n//\n\
                    O\tonion\nS\tchopped\nS\tin\t[bowl]\nM\tfry\nO\tonion\nS\tfried\n//\n";
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let idx = FindIndex::build(&foon);
        let found = idx.find(&foon, "chopped onoin in bowl", 3);
        assert_eq!(found.len(), 3);
        let best = crate::write::object_line(&foon, found[0].object);
        assert_eq!(best, "onion (chopped) in [bowl]");
        assert!(found[0].score > found[1].score);
        assert!(idx.find(&foon, "zzz", 0).is_empty());
    }
}

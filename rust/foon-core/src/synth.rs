//! `synth`: a deterministic generator of realistic merged FOONs of any size, with a matching
//! kitchen, goal set and motion table.
//!
//! # What it is calibrated on
//!
//! The course `FOON.txt` (2,376 units) and the lab's universal FOONs, which agree with it
//! within a few percent: 3.0 inputs and 1.9 outputs per unit, 8.6 objects per label, 14.5%
//! of produced objects with several producers (`bowl empty` has 51), 0.68 states per
//! object (45% with none), 55% of objects with an ingredient list and 65% with a container,
//! 90% of units with an ingredient list and 96% with a container, 6% of units passing a
//! stateful object through (`stove on` in and out), one connected component holding 99.9%
//! of the units, a cycle of 41% of the objects through the shared empty vessels, and the
//! motion mix of `motion.txt`'s 129 motions. `tests/test_synth.py` measures all of these
//! with one function on both the course FOON and generated ones.
//!
//! # The model
//!
//! A generated FOON is a merge of *recipes* over a shared vocabulary:
//!
//! - **Vocabulary.** Main ingredients (64 of the course's most used produce, meats and
//!   staples, weighted by their course use, then a tail `ingredient_t<j>` of `0.5·N^0.6`
//!   labels), additions (53 named: salt, water, oil, spices..., then a tail `seasoning_<j>`
//!   of `0.3·N^0.6`), working and serving vessels, cutting surfaces, the containers raw
//!   items come in, stateless tools, appliances (`off`/`on`), dish names (then
//!   `dish_<j>`), states, and the course's 129 motions with their counts and rates. Each
//!   item's raw states (none, one or two), raw container and prepared states are a fixed
//!   function of (seed, item).
//! - **Shared preparation (the catalogue).** Main ingredient `x` has `V(x)` preparation
//!   units: `x raw` (or, in every other variant, `x` already prepared once) + a
//!   tool (+ an empty surface) → `x prepared in [surface]` (+ the surface holding `{x}`).
//!   `V(x)` is a randomised rounding of 1.5 units per expected use of `x` (2 shared items a
//!   recipe, recipes estimated as `N/16`), at most 240; variants differ in motion, tool and
//!   input form, so popular prepared items have many producers, as in a merged FOON. The
//!   catalogue never takes more than a third of the units.
//! - **Recipes.** Recipe `r` has `3 + Geometric(mean 13)` units (at most 80) and a
//!   signature ingredient `ingredient_<r>` of its own (its distinctive item; its raw form
//!   is in the kitchen). Unit 1 prepares the signature; unit 2 puts it and 1–3 shared
//!   prepared items (80% named, by weight; 20% from the tail, skewed to its head) into an
//!   empty working vessel. Each further unit takes a motion from the course mix without
//!   the cutting motions (the catalogue's) and acts by its kind: *adding* puts an addition
//!   in (raw, from its container, sometimes with the container holding it and a tool; the
//!   item then lies in the vessel and the emptied container may come out; at most 15
//!   ingredients), or, 45% of the time, *transfers* the contents with 1–2 items in it to
//!   another empty vessel (the first may come back empty); *mixing and cooking* gives the
//!   vessel a new state, takes up to 3 items in it along (the first changing state), puts a
//!   vessel that sits on nothing on the stove or in the oven for cooking motions, and
//!   passes the appliance through (a self-loop); *switching* turns an appliance on or off
//!   with the vessel on it. The last unit serves the dish (`dish ready {contents} in
//!   [plate]`), and the working vessel often comes back empty: other recipes start from
//!   it, which closes the big cycle. A stateless tool comes back out in 15% of units.
//! - **Exact size, no duplicates.** Every unit of recipe `r` makes an object whose label or
//!   ingredient list holds `ingredient_<r>`; catalogue units never do; catalogue variants
//!   of one item differ by construction; within a recipe, every working-vessel output
//!   differs from the earlier ones at the same contents. So no two units are equal and the
//!   file holds exactly `units` units after duplicates are dropped: the catalogue takes
//!   what it needs first, recipes the rest (the last one cut short).
//! - **Determinism and scale.** Every draw comes from a `SplitMix64` stream keyed by (seed,
//!   what, index), so a recipe's bytes depend on (seed, units, r) only. Recipes are cut
//!   into chunks of 256 (each with its share of the catalogue), generated in parallel with
//!   rayon, and written in order: the bytes never depend on the thread count, and memory
//!   is a batch of chunks (2 per thread), not the FOON.
//! - **Kitchen.** Every raw object: each item's raw form (an addition also as its container
//!   holding it), empty vessels, tools, appliances off; 0.6% of the raw ingredients are
//!   withheld (seeded), so that about 95% of the dishes are derivable, as 95.3% of the
//!   course's final products are with the course kitchen and utensils.
//! - **Goals.** The dishes of recipes spread evenly over the FOON.

use std::io::Write;
use std::path::Path;

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::model::ObjectSpec;

/// The largest number of units `synth` makes (ids are u32).
pub const MAX_UNITS: u64 = u32::MAX as u64;

/// What to generate.
#[derive(Debug, Clone, Copy)]
pub struct SynthOptions {
    /// Functional units in the file (after duplicates are dropped: there are none).
    pub units: u64,
    /// Seed: the same seed gives the same bytes.
    pub seed: u64,
    /// Worker threads (`None`: rayon's default). The bytes do not depend on it.
    pub threads: Option<usize>,
}

/// What one generation wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SynthReport {
    pub units: u64,
    pub bytes: u64,
    pub recipes: u64,
}

// ---------------------------------------------------------------- vocabulary

/// Course motions: name, units using it in `FOON.txt`, success rate in `motion.txt`.
const MOTIONS: &[(&str, u32, f64)] = &[
    ("pour", 539, 0.90),
    ("pick-and-place", 373, 0.80),
    ("sprinkle", 122, 0.30),
    ("mix", 95, 0.90),
    ("stir", 70, 0.80),
    ("scoop and pour", 65, 0.60),
    ("scrape", 64, 0.60),
    ("cook and stir", 52, 0.70),
    ("cook", 50, 0.20),
    ("remove", 49, 0.65),
    ("chop", 48, 0.10),
    ("cut", 46, 0.15),
    ("pour and scrape", 42, 0.50),
    ("scoop", 35, 0.80),
    ("slice", 33, 0.15),
    ("peel", 32, 0.10),
    ("spread", 29, 0.20),
    ("put inside", 29, 0.30),
    ("turn on", 27, 0.30),
    ("turn off", 23, 0.30),
    ("flip", 22, 0.15),
    ("bake", 22, 0.40),
    ("heat", 22, 0.10),
    ("beat", 20, 0.85),
    ("grate", 19, 0.10),
    ("open", 18, 0.30),
    ("cover", 17, 0.40),
    ("blend", 17, 0.90),
    ("grind", 17, 0.40),
    ("crack", 16, 0.20),
    ("uncover", 16, 0.40),
    ("squeeze", 13, 0.10),
    ("detach", 13, 0.40),
    ("wash", 13, 0.40),
    ("roll", 12, 0.10),
    ("dice", 12, 0.15),
    ("shake", 12, 0.90),
    ("insert", 11, 0.70),
    ("attach", 10, 0.20),
    ("shape", 9, 0.40),
    ("boil", 9, 0.50),
    ("place", 9, 0.80),
    ("dip", 7, 0.90),
    ("spray", 7, 0.30),
    ("fold", 7, 0.15),
    ("scrape and pour", 7, 0.70),
    ("press", 7, 0.30),
    ("drain", 7, 0.80),
    ("mash", 7, 0.50),
    ("measure", 6, 0.20),
    ("preheat", 6, 0.60),
    ("rinse", 6, 0.60),
    ("pour and stir", 6, 0.60),
    ("fill", 5, 0.60),
    ("unwrap", 5, 0.20),
    ("cut open", 5, 0.10),
    ("chill", 5, 0.40),
    ("close", 5, 0.30),
    ("wrap", 5, 0.15),
    ("cut off ends", 5, 0.15),
    ("knead", 5, 0.20),
    ("simmer", 4, 0.30),
    ("throw away", 4, 0.70),
    ("brush", 4, 0.70),
    ("pour and mix", 4, 0.90),
    ("fry", 3, 0.10),
    ("pour and spread", 3, 0.20),
    ("pour and blend", 3, 0.70),
    ("core", 3, 0.20),
    ("rip open", 3, 0.10),
    ("tear and place", 3, 0.30),
    ("melt", 3, 0.75),
    ("grind and sprinkle", 2, 0.30),
    ("light", 2, 0.40),
    ("scoop and spread", 2, 0.40),
    ("add", 2, 0.85),
    ("tear apart", 2, 0.10),
    ("squeeze and scrape", 2, 0.15),
    ("coat", 2, 0.55),
    ("take out", 2, 0.50),
    ("divide", 2, 0.30),
    ("toast", 2, 0.60),
    ("tear", 2, 0.20),
    ("poke", 2, 0.80),
    ("soak", 2, 0.80),
    ("pull apart", 2, 0.20),
    ("grind and pour", 2, 0.60),
    ("fold and pinch", 2, 0.10),
    ("press and cook", 2, 0.60),
    ("stir and strain", 1, 0.40),
    ("flip and stack", 1, 0.10),
    ("sift", 1, 0.10),
    ("whisk", 1, 0.70),
    ("cut with slits", 1, 0.10),
    ("pour and strain", 1, 0.40),
    ("drip", 1, 0.30),
    ("skim", 1, 0.15),
    ("break apart", 1, 0.20),
    ("mix and pour", 1, 0.90),
    ("take apart", 1, 0.30),
    ("scoop and place", 1, 0.80),
    ("mince", 1, 0.15),
    ("freeze", 1, 0.65),
    ("brew", 1, 0.65),
    ("cook and shake", 1, 0.80),
    ("cook and spread", 1, 0.80),
    ("tear and cover", 1, 0.30),
    ("ferment", 1, 0.30),
    ("break", 1, 0.40),
    ("rub", 1, 0.70),
    ("rim", 1, 0.60),
    ("tuck ends", 1, 0.40),
    ("broil", 1, 0.70),
    ("flip and place", 1, 0.10),
    ("place and spread", 1, 0.60),
    ("combine", 1, 0.60),
    ("make slits", 1, 0.30),
    ("cut off skin", 1, 0.20),
    ("defrost", 1, 0.70),
    ("cut in half", 1, 0.15),
    ("cool down", 1, 0.70),
    ("fry and flip", 1, 0.10),
    ("mix and mash", 1, 0.80),
    ("shave", 1, 0.20),
    ("sit", 1, 0.70),
    ("cook and flip", 1, 0.60),
    ("roll and shape", 1, 0.40),
    ("stir and melt", 1, 0.80),
    ("stir and fry", 1, 0.80),
];

/// Main ingredients (prepared before use), weighted by their use in the course FOON.
const MAIN: &[(&str, u32)] = &[
    ("onion", 96),
    ("garlic", 84),
    ("potato", 44),
    ("lemon", 36),
    ("carrot", 36),
    ("bacon", 27),
    ("tomato", 25),
    ("apple", 21),
    ("mushroom", 20),
    ("sweet pepper", 19),
    ("cheese", 17),
    ("broccoli", 17),
    ("cilantro", 16),
    ("watermelon", 16),
    ("avocado", 16),
    ("lettuce", 16),
    ("celery", 16),
    ("basil", 15),
    ("salmon", 15),
    ("green pepper", 13),
    ("parsley", 13),
    ("sausage", 13),
    ("beefsteak", 13),
    ("scallion", 12),
    ("green bean", 12),
    ("zucchini", 12),
    ("bread", 12),
    ("green onion", 11),
    ("chive", 10),
    ("brussel sprout", 10),
    ("cucumber", 9),
    ("strawberry", 9),
    ("rosemary", 9),
    ("cabbage", 9),
    ("egg", 9),
    ("sweet potato", 8),
    ("gruyere", 8),
    ("mozzarella", 8),
    ("mango", 8),
    ("porkchop", 6),
    ("cheddar", 7),
    ("black olive", 6),
    ("thyme", 6),
    ("beef", 6),
    ("cherry tomato", 6),
    ("tofu", 6),
    ("lime", 6),
    ("shallot", 6),
    ("lemon gras", 6),
    ("corn", 6),
    ("orange", 6),
    ("chicken breast", 6),
    ("jalapeno", 5),
    ("radish", 5),
    ("chili pepper", 5),
    ("banana", 4),
    ("ginger", 4),
    ("green olive", 4),
    ("eggplant", 4),
    ("spinach", 4),
    ("shrimp", 4),
    ("pineapple", 3),
    ("peach", 3),
    ("kale", 3),
];

/// Additions (used raw), weighted by their use in the course FOON.
const ADDITIONS: &[(&str, u32)] = &[
    ("salt", 113),
    ("water", 84),
    ("butter", 72),
    ("black pepper", 67),
    ("flour", 54),
    ("olive oil", 54),
    ("sugar", 48),
    ("milk", 34),
    ("vanilla extract", 16),
    ("white rice", 15),
    ("soy sauce", 14),
    ("baking powder", 13),
    ("oregano", 13),
    ("salad dressing", 13),
    ("black bean", 12),
    ("ground beef", 12),
    ("parmesan", 11),
    ("sour cream", 11),
    ("paprika", 11),
    ("mayonnaise", 11),
    ("mustard", 10),
    ("chocolate chip", 10),
    ("instant coffee", 9),
    ("cinnamon", 9),
    ("ice", 8),
    ("breadcrumb", 7),
    ("baking soda", 7),
    ("broth", 7),
    ("coriander", 7),
    ("sesame oil", 7),
    ("vegetable oil", 7),
    ("chicken broth", 6),
    ("condensed milk", 6),
    ("heavy cream", 6),
    ("corn starch", 6),
    ("worcestershire sauce", 6),
    ("cocoa powder", 5),
    ("white pepper", 5),
    ("yogurt", 5),
    ("maple syrup", 5),
    ("powdered sugar", 5),
    ("honey", 5),
    ("vinegar", 4),
    ("ketchup", 4),
    ("cumin", 4),
    ("half-and-half", 4),
    ("curry paste", 4),
    ("peanut butter", 4),
    ("white wine", 4),
    ("lime juice", 4),
    ("oat", 4),
    ("brown sugar", 3),
    ("chili powder", 3),
];

/// Working vessels, weighted by how often the course uses them.
const VESSELS: &[(&str, u32)] = &[
    ("bowl", 360),
    ("cooking pan", 176),
    ("pot", 126),
    ("mixing bowl", 124),
    ("baking tray", 72),
    ("blender jar", 46),
    ("skillet", 40),
    ("saucepan", 30),
    ("frying pan", 30),
    ("salad bowl", 25),
    ("jar", 20),
    ("drinking glass", 20),
];
/// Serving vessels.
const SERVING: &[(&str, u32)] = &[
    ("plate", 89),
    ("bowl", 30),
    ("drinking glass", 15),
    ("serving plate", 10),
    ("salad bowl", 8),
    ("container", 8),
];
/// Where ingredients are prepared.
const SURFACES: &[(&str, u32)] = &[("cutting board", 84), ("plate", 10), ("bowl", 10)];
/// Containers raw ingredients come in.
const RAW_CONTAINERS: &[(&str, u32)] = &[
    ("measuring cup", 53),
    ("packet", 61),
    ("bottle", 40),
    ("jar", 20),
    ("shaker", 25),
    ("measuring spoon", 15),
    ("container", 15),
    ("can", 8),
];
/// Stateless utensils for preparing.
const PREP_TOOLS: &[(&str, u32)] = &[
    ("knife", 191),
    ("peeler", 9),
    ("grater", 17),
    ("fork", 20),
    ("scissors", 8),
    ("pizza cutter", 2),
];
/// Stateless utensils for adding and mixing.
const MIX_TOOLS: &[(&str, u32)] = &[
    ("spoon", 148),
    ("spatula", 83),
    ("turner", 67),
    ("tong", 47),
    ("whisk", 34),
    ("fork", 18),
    ("ladle", 10),
];
/// Appliances a vessel sits on or in.
const APPLIANCES: &[(&str, u32)] = &[
    ("stove", 136),
    ("oven", 87),
    ("microwave", 10),
    ("grill", 20),
    ("toaster", 5),
];
const RAW_MAIN_STATES: &[(&str, u32)] = &[
    ("whole", 106),
    ("uncooked", 30),
    ("raw", 19),
    ("unpeeled", 18),
    ("frozen", 10),
    ("washed", 6),
    ("block", 10),
    ("stem", 7),
    ("leaf", 12),
];
const RAW_ADD_STATES: &[(&str, u32)] = &[
    ("liquid", 44),
    ("powder", 41),
    ("ground", 41),
    ("granulated", 27),
    ("dried", 28),
    ("softened", 15),
    ("creamy", 14),
    ("thick liquid", 6),
    ("cubed", 12),
    ("unmelted", 11),
    ("paste", 6),
];
const PREP_STATES: &[(&str, u32)] = &[
    ("chopped", 176),
    ("sliced", 126),
    ("peeled", 69),
    ("halved", 48),
    ("diced", 40),
    ("grated", 35),
    ("minced", 24),
    ("cubed", 22),
    ("crushed", 8),
    ("mashed", 7),
    ("julienned", 4),
    ("shredded", 6),
];
const MIX_STATES: &[(&str, u32)] = &[
    ("mixed", 122),
    ("cooked", 153),
    ("hot", 143),
    ("partly cooked", 61),
    ("thick liquid", 43),
    ("creamy", 40),
    ("fried", 38),
    ("beaten", 29),
    ("baked", 28),
    ("melted", 23),
    ("toasted", 19),
    ("heated", 15),
    ("sauteed", 13),
    ("seasoned", 12),
    ("whipped", 10),
    ("boiled", 8),
    ("blended", 8),
    ("chilled", 6),
    ("covered", 17),
];
const DISH_STATES: &[(&str, u32)] = &[
    ("ready", 20),
    ("cooked", 20),
    ("mixed", 15),
    ("baked", 8),
    ("garnished", 4),
];
const DISHES: &[&str] = &[
    "salad",
    "soup",
    "pancake",
    "omelette",
    "pasta",
    "stir fry",
    "sandwich",
    "smoothie",
    "cake",
    "cookie",
    "curry",
    "stew",
    "risotto",
    "taco",
    "burrito",
    "quesadilla",
    "frittata",
    "casserole",
    "pie",
    "muffin",
    "brownie",
    "salsa",
    "guacamole",
    "noodle soup",
    "fried rice",
    "mashed potato",
    "french toast",
    "pizza",
    "lasagna",
    "chili",
    "sauce",
    "dip",
    "cocktail",
    "milkshake",
    "porridge",
    "burger",
    "skewer",
    "roast",
    "gratin",
    "tart",
];

// ---------------------------------------------------------------- randomness

fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A `SplitMix64` stream keyed by (seed, stream kind, index).
struct Rng(u64);

impl Rng {
    fn new(seed: u64, kind: u64, index: u64) -> Self {
        Self(mix64(
            mix64(seed ^ 0x5eed_f00d) ^ mix64(kind.wrapping_mul(0x9e37) ^ index),
        ))
    }
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix64(self.0)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    fn below(&mut self, n: usize) -> usize {
        (((self.next() >> 32) * n as u64) >> 32) as usize
    }
    fn weighted<'a>(&mut self, table: &[(&'a str, u32)]) -> &'a str {
        table[self.weighted_index(table.iter().map(|t| t.1))].0
    }
    fn weighted_index(&mut self, weights: impl Iterator<Item = u32> + Clone) -> usize {
        let total: u64 = weights.clone().map(u64::from).sum();
        let mut x = (self.next() >> 1) % total.max(1);
        let mut last = 0;
        for (i, w) in weights.enumerate() {
            if x < u64::from(w) {
                return i;
            }
            x -= u64::from(w);
            last = i;
        }
        last
    }
}

// ---------------------------------------------------------------- motion kinds

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    /// Cutting, peeling...: the catalogue's motions.
    Prepare,
    /// Something goes into the working vessel.
    Add,
    /// The vessel's contents change state.
    Mix,
    /// An appliance is turned on or off.
    Switch,
}

fn kind_of(motion: &str) -> Kind {
    const ADD: &[&str] = &[
        "pour", "sprinkle", "place", "scoop", "add", "fill", "insert", "put", "spread", "coat",
        "dip", "brush", "drip", "spray", "rim", "combine", "measure",
    ];
    const PREPARE: &[&str] = &[
        "chop", "cut", "slice", "dice", "peel", "grate", "crack", "mince", "core", "tear",
        "squeeze", "grind", "mash", "shave", "rip", "break", "apart", "wash", "rinse", "roll",
        "shape", "fold", "press", "knead", "poke", "slits", "divide", "open", "unwrap", "shell",
    ];
    const SWITCH: &[&str] = &["turn on", "turn off", "preheat", "light"];
    if SWITCH.iter().any(|k| motion.contains(k)) {
        Kind::Switch
    } else if ADD.iter().any(|k| motion.contains(k)) {
        Kind::Add
    } else if PREPARE.iter().any(|k| motion.contains(k)) {
        Kind::Prepare
    } else {
        Kind::Mix
    }
}

/// Motion tables by kind, built once per generation.
struct Motions {
    prepare: Vec<(&'static str, u32)>,
    recipe: Vec<(&'static str, u32)>,
    add: Vec<(&'static str, u32)>,
}

impl Motions {
    fn new() -> Self {
        let pick = |f: &dyn Fn(Kind) -> bool| -> Vec<(&'static str, u32)> {
            MOTIONS
                .iter()
                .filter(|m| f(kind_of(m.0)))
                .map(|m| (m.0, m.1))
                .collect()
        };
        Self {
            prepare: pick(&|k| k == Kind::Prepare),
            recipe: pick(&|k| k != Kind::Prepare),
            add: pick(&|k| k == Kind::Add),
        }
    }
}

// ---------------------------------------------------------------- sizes and items

/// Units of a recipe before the cut: `3 + Geometric(mean 13)`, at most 80.
fn recipe_len(seed: u64, r: u64) -> u64 {
    let mut g = Rng::new(seed, 1, r);
    let u = g.unit().max(1e-12);
    let extra = (u.ln() / (1.0 - 1.0 / 13.0f64).ln()).floor() as u64;
    (3 + extra).min(80)
}

/// How many shared items a recipe puts in at its start, on average.
const SHARED_PER_RECIPE: f64 = 2.0;
/// Catalogue units per expected use of a main ingredient.
const UNITS_PER_USE: f64 = 1.5;
/// Share of shared picks that go to the named vocabulary (the rest to the tail).
const NAMED_SHARE: f64 = 0.8;
/// Most variants one item's catalogue has.
const MAX_VARIANTS: u64 = 240;
/// Most ingredients a working vessel holds (the course's largest list has 15).
const MAX_CONTENTS: usize = 15;
/// Share of raw ingredients left out of the kitchen.
const KITCHEN_MISS: f64 = 0.006;
/// Recipes a chunk holds.
const CHUNK: u64 = 256;

/// The sizes of one generation.
#[derive(Debug, Clone, Copy)]
struct Plan {
    seed: u64,
    units: u64,
    /// Tail main ingredients `ingredient_t<j>` (shared), and tail additions.
    main_tail: u64,
    add_tail: u64,
    /// Catalogue units in all.
    catalogue: u64,
    /// Recipes, and the length of the last (cut) one.
    recipes: u64,
    last_len: u64,
    named_weight: u64,
    /// The catalogue stops at this item, which keeps `cut_variants` of its variants.
    cut_item: u64,
    cut_variants: u64,
}

impl Plan {
    fn new(seed: u64, units: u64) -> Result<Self> {
        if units == 0 {
            return Err(Error::Invalid("units must be at least 1".into()));
        }
        if units > MAX_UNITS {
            return Err(Error::Invalid(format!(
                "units must be at most {MAX_UNITS} (ids are 32-bit), not {units}"
            )));
        }
        let n = units as f64;
        let main_tail = (0.5 * n.powf(0.6)) as u64;
        let add_tail = (0.3 * n.powf(0.6)) as u64;
        let named_weight = MAIN.iter().map(|m| u64::from(m.1)).sum();
        let mut p = Self {
            seed,
            units,
            main_tail,
            add_tail,
            catalogue: 0,
            recipes: 0,
            last_len: 0,
            named_weight,
            cut_item: 0,
            cut_variants: 0,
        };
        // The catalogue never takes more than a third of the units: it is cut at the item
        // where it would.
        let cap = units / 3;
        let mut cat = 0u64;
        p.cut_item = p.main_items();
        for x in 0..p.main_items() {
            let v = p.full_variants(x);
            if cat + v > cap {
                p.cut_item = x;
                p.cut_variants = cap - cat;
                cat = cap;
                break;
            }
            cat += v;
        }
        p.catalogue = cat;
        let mut left = units - p.catalogue;
        let mut r = 0u64;
        while left > 0 {
            let l = recipe_len(seed, r).min(left);
            left -= l;
            p.last_len = l;
            r += 1;
        }
        p.recipes = r;
        Ok(p)
    }

    fn main_items(&self) -> u64 {
        MAIN.len() as u64 + self.main_tail
    }

    /// The probability that one shared pick is main ingredient `x`.
    fn pick_prob(&self, x: u64) -> f64 {
        let named = MAIN.len() as u64;
        if x < named {
            NAMED_SHARE * f64::from(MAIN[x as usize].1) / self.named_weight as f64
        } else {
            let t = self.main_tail as f64;
            let j = (x - named) as f64;
            (1.0 - NAMED_SHARE) * (((j + 1.0) / t).sqrt() - (j / t).sqrt())
        }
    }

    /// Catalogue units of main ingredient `x`.
    fn variants(&self, x: u64) -> u64 {
        match x.cmp(&self.cut_item) {
            std::cmp::Ordering::Less => self.full_variants(x),
            std::cmp::Ordering::Equal => self.cut_variants,
            std::cmp::Ordering::Greater => 0,
        }
    }

    /// Catalogue units of `x` before the cap: a randomised rounding of its expected uses
    /// (recipes estimated as units / 16) times [`UNITS_PER_USE`].
    fn full_variants(&self, x: u64) -> u64 {
        let recipes = self.units as f64 / 16.0;
        let uses = recipes * SHARED_PER_RECIPE * self.pick_prob(x);
        let mut g = Rng::new(self.seed, 2, x);
        ((uses * UNITS_PER_USE + g.unit()).floor() as u64).min(MAX_VARIANTS)
    }

    /// A shared pick of a main ingredient: named (by weight) or from the tail.
    fn pick_main(&self, g: &mut Rng) -> u64 {
        if self.main_tail == 0 || g.chance(NAMED_SHARE) {
            g.weighted_index(MAIN.iter().map(|m| m.1)) as u64
        } else {
            let u = g.unit();
            MAIN.len() as u64 + ((self.main_tail as f64 * u * u) as u64).min(self.main_tail - 1)
        }
    }

    fn pick_addition(&self, g: &mut Rng) -> u64 {
        if self.add_tail == 0 || g.chance(0.85) {
            g.weighted_index(ADDITIONS.iter().map(|m| m.1)) as u64
        } else {
            let u = g.unit();
            ADDITIONS.len() as u64 + ((self.add_tail as f64 * u * u) as u64).min(self.add_tail - 1)
        }
    }
}

/// A main ingredient's label and fixed properties.
struct Main {
    label: String,
    raw_states: Vec<&'static str>,
    raw_container: Option<&'static str>,
    prepared: [&'static str; 2],
    surface: &'static str,
}

/// Main ingredient `x`: named for `x < MAIN.len()`, then `ingredient_t<j>` (shared tail),
/// and the signatures `ingredient_<r>` (given as `Err(r)`).
fn main_item(seed: u64, x: std::result::Result<u64, u64>) -> Main {
    let (label, key) = match x {
        Ok(x) if (x as usize) < MAIN.len() => (MAIN[x as usize].0.to_owned(), x),
        Ok(x) => (format!("ingredient_t{}", x - MAIN.len() as u64), x),
        Err(r) => (format!("ingredient_{r}"), u64::MAX - r),
    };
    let mut g = Rng::new(seed, 3, key);
    let raw_states = states_of(&mut g, RAW_MAIN_STATES, 0.12, 0.2);
    let raw_container = g.chance(0.15).then(|| g.weighted(RAW_CONTAINERS));
    let a = g.weighted(PREP_STATES);
    let mut b = g.weighted(PREP_STATES);
    if b == a {
        b = PREP_STATES
            [(PREP_STATES.iter().position(|s| s.0 == a).unwrap_or(0) + 1) % PREP_STATES.len()]
        .0;
    }
    let surface = g.weighted(SURFACES);
    Main {
        label,
        raw_states,
        raw_container,
        prepared: [a, b],
        surface,
    }
}

/// An addition's label, raw state and container.
/// Raw states: none (`none` of the time), two (`two`), else one, drawn from `table`.
fn states_of(g: &mut Rng, table: &[(&'static str, u32)], none: f64, two: f64) -> Vec<&'static str> {
    let u = g.unit();
    if u < none {
        return Vec::new();
    }
    let a = g.weighted(table);
    let b = g.weighted(table);
    if u < none + two && a != b {
        vec![a, b]
    } else {
        vec![a]
    }
}

fn addition(seed: u64, a: u64) -> (String, Vec<&'static str>, Option<&'static str>) {
    let label = if (a as usize) < ADDITIONS.len() {
        ADDITIONS[a as usize].0.to_owned()
    } else {
        format!("seasoning_{}", a - ADDITIONS.len() as u64)
    };
    let mut g = Rng::new(seed, 4, a);
    let state = states_of(&mut g, RAW_ADD_STATES, 0.3, 0.1);
    let container = g.chance(0.8).then(|| g.weighted(RAW_CONTAINERS));
    (label, state, container)
}

// ---------------------------------------------------------------- writing objects

struct Obj<'a> {
    label: &'a str,
    states: &'a [&'a str],
    ingredients: &'a [String],
    container: Option<&'a str>,
}

fn obj<'a>(label: &'a str, states: &'a [&'a str], container: Option<&'a str>) -> Obj<'a> {
    Obj {
        label,
        states,
        ingredients: &[],
        container,
    }
}

fn put(buf: &mut Vec<u8>, o: &Obj<'_>) {
    buf.extend_from_slice(b"O\t");
    buf.extend_from_slice(o.label.as_bytes());
    buf.push(b'\n');
    for s in o.states {
        buf.extend_from_slice(b"S\t");
        buf.extend_from_slice(s.as_bytes());
        buf.push(b'\n');
    }
    if !o.ingredients.is_empty() {
        buf.extend_from_slice(b"S\tcontains\t{");
        for (i, x) in o.ingredients.iter().enumerate() {
            if i > 0 {
                buf.push(b',');
            }
            buf.extend_from_slice(x.as_bytes());
        }
        buf.extend_from_slice(b"}\n");
    }
    if let Some(c) = o.container {
        buf.extend_from_slice(b"S\tin\t[");
        buf.extend_from_slice(c.as_bytes());
        buf.extend_from_slice(b"]\n");
    }
}

fn unit(buf: &mut Vec<u8>, inputs: &[Obj<'_>], motion: &str, outputs: &[Obj<'_>]) {
    for o in inputs {
        put(buf, o);
    }
    buf.extend_from_slice(b"M\t");
    buf.extend_from_slice(motion.as_bytes());
    buf.push(b'\n');
    for o in outputs {
        put(buf, o);
    }
    buf.extend_from_slice(b"//\n");
}

// ---------------------------------------------------------------- catalogue

/// Writes catalogue units `from..to` of main ingredient `x` (variants in order).
fn catalogue_item(p: &Plan, m: &Motions, x: u64, variants: u64, buf: &mut Vec<u8>) {
    let it = main_item(p.seed, Ok(x));
    let nm = m.prepare.len() as u64;
    let nt = PREP_TOOLS.len() as u64;
    let mut g = Rng::new(p.seed, 5, x);
    let m0 = g.weighted_index(m.prepare.iter().map(|t| t.1)) as u64;
    let contains = [it.label.clone()];
    let empty = ["empty"];
    for v in 0..variants {
        // Distinct (input form, motion, tool) for distinct v: mixed radix over v (odd
        // variants start from the item prepared once: `peeled` -> `chopped`).
        let chained = v % 2 == 1;
        let motion = m.prepare[((m0 + v / 2) % nm) as usize].0;
        let tool = PREP_TOOLS[((v / 2 / nm) % nt) as usize].0;
        let target = it.prepared[usize::from(chained)];
        let from_states = [it.prepared[0]];
        let mut g = Rng::new(p.seed, 6, x.wrapping_mul(1024) ^ v);
        let mut ins = Vec::with_capacity(3);
        if chained {
            ins.push(obj(&it.label, &from_states, Some(it.surface)));
        } else {
            ins.push(obj(&it.label, &it.raw_states, it.raw_container));
        }
        ins.push(obj(tool, &[], None));
        let with_surface = !chained && g.chance(0.7);
        if with_surface {
            ins.push(obj(it.surface, &empty, None));
        }
        if chained && g.chance(0.8) {
            // The surface holding the item, as the course writes it.
            ins.push(Obj {
                label: it.surface,
                states: &[],
                ingredients: &contains,
                container: None,
            });
        }
        let target = [target];
        let mut outs = vec![obj(&it.label, &target, Some(it.surface))];
        if g.chance(TOOL_BACK) {
            outs.push(obj(tool, &[], None));
        }
        if with_surface && g.chance(0.8) {
            outs.push(Obj {
                label: it.surface,
                states: &[],
                ingredients: &contains,
                container: None,
            });
        }
        unit(buf, &ins, motion, &outs);
    }
}

// ---------------------------------------------------------------- recipes

/// The working vessel of a recipe.
struct Vessel {
    label: &'static str,
    states: Vec<&'static str>,
    contents: Vec<String>,
    container: Option<&'static str>,
    /// Items seen inside it (`label states in [vessel]`), oldest first.
    inside: Vec<(String, Vec<&'static str>)>,
}

impl Vessel {
    fn obj(&self) -> Obj<'_> {
        Obj {
            label: self.label,
            states: &self.states,
            ingredients: &self.contents,
            container: self.container,
        }
    }
}

/// A recipe's prepared form of main ingredient `x` (its catalogue output, or its raw form
/// when it has no catalogue).
fn prepared_form(p: &Plan, it: &Main, x: u64) -> (Vec<&'static str>, Option<&'static str>) {
    if p.variants(x) > 0 {
        (vec![it.prepared[0]], Some(it.surface))
    } else {
        (it.raw_states.clone(), it.raw_container)
    }
}

/// Writes recipe `r` (its first `len` units) and returns its dish.
fn recipe(p: &Plan, m: &Motions, r: u64, len: u64, buf: &mut Vec<u8>) -> Option<ObjectSpec> {
    let mut g = Rng::new(p.seed, 7, r);
    let sig = main_item(p.seed, Err(r));
    let empty = ["empty"];
    // 1. The signature is prepared.
    let motion = g.weighted(&m.prepare);
    let tool = g.weighted(PREP_TOOLS);
    let raw = &sig.raw_states;
    let prep = [sig.prepared[0]];
    unit(
        buf,
        &[
            obj(&sig.label, raw, sig.raw_container),
            obj(tool, &[], None),
        ],
        motion,
        &[obj(&sig.label, &prep, Some(sig.surface))],
    );
    if len == 1 {
        return None;
    }
    // 2. It goes into the working vessel with 1-3 shared prepared items.
    let mut w = Vessel {
        label: g.weighted(VESSELS),
        states: Vec::new(),
        contents: vec![sig.label.clone()],
        container: None,
        inside: Vec::new(),
    };
    let shared = 1 + g.below(3);
    let mut picks: Vec<(u64, Main)> = Vec::with_capacity(shared);
    for _ in 0..shared {
        let x = p.pick_main(&mut g);
        if picks.iter().all(|q| q.0 != x) {
            picks.push((x, main_item(p.seed, Ok(x))));
        }
    }
    let forms: Vec<(Vec<&'static str>, Option<&'static str>)> = picks
        .iter()
        .map(|(x, it)| prepared_form(p, it, *x))
        .collect();
    {
        let mut ins = vec![
            obj(w.label, &empty, None),
            obj(&sig.label, &prep, Some(sig.surface)),
        ];
        for ((_, it), (s, c)) in picks.iter().zip(&forms) {
            ins.push(obj(&it.label, s, *c));
        }
        for (_, it) in &picks {
            w.contents.push(it.label.clone());
        }
        let surface_back = g.chance(0.5);
        let mut outs = vec![w.obj()];
        if surface_back {
            outs.push(obj(sig.surface, &empty, None));
        }
        let mut inside = Vec::new();
        for ((_, it), (st, _)) in picks.iter().zip(&forms) {
            if g.chance(0.7) {
                inside.push((it.label.clone(), st.clone()));
            }
        }
        let inside_objs: Vec<Obj<'_>> = inside
            .iter()
            .map(|(l, st)| obj(l, st, Some(w.label)))
            .collect();
        outs.extend(inside_objs);
        unit(buf, &ins, g.weighted(&m.add), &outs);
        w.inside = inside;
    }
    // 3. Middle steps; 4. serving (the last unit when the recipe is not cut). `seen` holds
    // the vessel outputs made at the current contents: a step never repeats one.
    let serve_at = recipe_len(p.seed, r) - 1;
    let mut seen: Vec<Key> = vec![w.key()];
    for step in 2..len {
        if step == serve_at {
            return Some(serve(&mut g, m, &w, buf));
        }
        let motion = g.weighted(&m.recipe);
        let mut kind = kind_of(motion);
        if kind == Kind::Add && (w.contents.len() >= MAX_CONTENTS || g.chance(TRANSFER_SHARE)) {
            kind = Kind::Prepare; // a transfer to another vessel
        }
        let before = w.obj_spec();
        let done = match kind {
            Kind::Mix => {
                heat(motion, &mut w);
                let fresh = restate(&mut g, &mut w, &seen);
                if fresh {
                    mix_step(&mut g, motion, &mut w, &before, buf);
                }
                fresh
            }
            Kind::Prepare => transfer(&mut g, motion, &mut w, &before, &seen, buf),
            Kind::Switch => switch(&mut g, motion, &mut w, &before, &seen, buf),
            Kind::Add => false,
        };
        if done {
            seen.push(w.key());
        } else {
            let motion = if kind == Kind::Add {
                motion
            } else {
                m.add[0].0
            };
            add(p, &mut g, motion, &mut w, &before, buf);
            seen = vec![w.key()];
        }
    }
    None
}

/// A cooking motion puts a vessel that sits on nothing on the stove (or in the oven).
fn heat(motion: &str, w: &mut Vessel) {
    const HOT: &[&str] = &["cook", "heat", "fry", "boil", "simmer", "melt", "saute"];
    const OVEN: &[&str] = &["bake", "broil", "toast", "roast"];
    if w.container.is_none() {
        if OVEN.iter().any(|k| motion.contains(k)) {
            w.container = Some("oven");
        } else if HOT.iter().any(|k| motion.contains(k)) {
            w.container = Some("stove");
        }
    }
}

/// A working vessel's identity at fixed contents: label, states, container.
type Key = (&'static str, Vec<&'static str>, Option<&'static str>);

impl Vessel {
    fn key(&self) -> Key {
        (self.label, self.states.clone(), self.container)
    }
}

/// Share of adding motions that move the contents to another vessel instead.
const TRANSFER_SHARE: f64 = 0.45;
/// Share of units whose stateless tool is written among the outputs too.
const TOOL_BACK: f64 = 0.15;

/// The contents move to another (empty) vessel; the first comes back empty. False when
/// no new vessel output was found.
fn transfer(
    g: &mut Rng,
    motion: &str,
    w: &mut Vessel,
    before: &Before,
    seen: &[Key],
    buf: &mut Vec<u8>,
) -> bool {
    for _ in 0..4 {
        let to = g.weighted(VESSELS);
        let states = if g.chance(0.6) {
            Vec::new()
        } else {
            w.states.clone()
        };
        let key = (to, states, None);
        if to == w.label || seen.contains(&key) {
            continue;
        }
        w.states = key.1;
        let from = w.label;
        w.label = to;
        w.container = None;
        let empty = ["empty"];
        let moved = w.inside.len().min(1 + g.below(2));
        let first = w.inside.len() - moved;
        let mut ins = vec![before.as_obj(), obj(to, &empty, None)];
        let mut outs = vec![w.obj()];
        for (l, st) in &w.inside[first..] {
            ins.push(obj(l, st, Some(from)));
            outs.push(obj(l, st, Some(to)));
        }
        if g.chance(0.45) {
            outs.push(obj(from, &empty, None));
        }
        unit(buf, &ins, motion, &outs);
        w.inside.drain(..first);
        return true;
    }
    false
}

/// An appliance is turned on (or off) with the vessel on it. False when no new vessel
/// output was found.
fn switch(
    g: &mut Rng,
    motion: &str,
    w: &mut Vessel,
    before: &Before,
    seen: &[Key],
    buf: &mut Vec<u8>,
) -> bool {
    let appliance = match w.container {
        Some(c) if APPLIANCES.iter().any(|a| a.0 == c) => c,
        _ => g.weighted(APPLIANCES),
    };
    let (from, to) = if motion == "turn off" {
        ("on", "off")
    } else {
        ("off", "on")
    };
    if w.container == Some(appliance)
        || seen.contains(&(w.label, w.states.clone(), Some(appliance)))
    {
        w.container = Some(appliance);
        if !restate(g, w, seen) {
            w.container = before.container;
            return false;
        }
    } else {
        w.container = Some(appliance);
    }
    let fs = [from];
    let ts = [to];
    unit(
        buf,
        &[obj(appliance, &fs, None), before.as_obj()],
        motion,
        &[obj(appliance, &ts, None), w.obj()],
    );
    true
}

/// Gives the vessel a state set not seen at its current contents; false if none found.
fn restate(g: &mut Rng, w: &mut Vessel, seen: &[Key]) -> bool {
    for _ in 0..6 {
        let s = g.weighted(MIX_STATES);
        let mut states: Vec<&'static str> = if g.chance(0.5) {
            w.states
                .iter()
                .copied()
                .filter(|x| *x != s)
                .take(1)
                .collect()
        } else {
            Vec::new()
        };
        states.push(s);
        let key = (w.label, states, w.container);
        if !seen.contains(&key) {
            w.states = key.1;
            return true;
        }
    }
    false
}

/// The vessel's contents change state (already set in `w`): items inside it come along,
/// the first sometimes changing too; an appliance it sits on is passed through.
fn mix_step(g: &mut Rng, motion: &str, w: &mut Vessel, before: &Before, buf: &mut Vec<u8>) {
    let on = w.container.filter(|c| APPLIANCES.iter().any(|a| a.0 == *c));
    let on_states = ["on"];
    let mut taken: Vec<usize> = Vec::new();
    let n = w.inside.len();
    for (i, p) in [
        (n.wrapping_sub(1), 0.8),
        (n.wrapping_sub(2), 0.55),
        (n.wrapping_sub(3), 0.3),
    ] {
        if i < n && g.chance(p) {
            taken.push(i);
        }
    }
    let new_state = w.states.last().copied().unwrap_or("mixed");
    let changed = taken
        .first()
        .copied()
        .filter(|&i| g.chance(0.7) && w.inside[i].1 != [new_state]);
    let changed_states = [new_state];
    {
        let mut ins = vec![before.as_obj()];
        for &i in &taken {
            ins.push(obj(&w.inside[i].0, &w.inside[i].1, Some(w.label)));
        }
        let mut outs = vec![w.obj()];
        if let Some(i) = changed {
            outs.push(obj(&w.inside[i].0, &changed_states, Some(w.label)));
        }
        if let Some(a) = on {
            if g.chance(0.6) {
                ins.push(obj(a, &on_states, None));
                outs.push(obj(a, &on_states, None));
            }
        }
        if g.chance(0.3) {
            let t = g.weighted(MIX_TOOLS);
            ins.push(obj(t, &[], None));
            if g.chance(TOOL_BACK) {
                outs.push(obj(t, &[], None));
            }
        }
        unit(buf, &ins, motion, &outs);
    }
    if let Some(i) = changed {
        w.inside[i].1 = vec![new_state];
    }
}

/// A vessel's state before a step, owned.
struct Before {
    label: &'static str,
    states: Vec<&'static str>,
    contents: Vec<String>,
    container: Option<&'static str>,
}

impl Before {
    fn as_obj(&self) -> Obj<'_> {
        Obj {
            label: self.label,
            states: &self.states,
            ingredients: &self.contents,
            container: self.container,
        }
    }
}

impl Vessel {
    fn obj_spec(&self) -> Before {
        Before {
            label: self.label,
            states: self.states.clone(),
            contents: self.contents.clone(),
            container: self.container,
        }
    }
}

/// An addition goes into the vessel (its contents grow, so its output is new).
fn add(p: &Plan, g: &mut Rng, motion: &str, w: &mut Vessel, before: &Before, buf: &mut Vec<u8>) {
    let mut a = p.pick_addition(g);
    let mut label;
    let mut tries = 0;
    loop {
        let (l, _, _) = addition(p.seed, a);
        label = l;
        if !w.contents.contains(&label) {
            break;
        }
        tries += 1;
        // After a few draws, the next addition in order (past the vocabulary only when
        // every addition is in already).
        a = if tries < 4 { p.pick_addition(g) } else { a + 1 };
    }
    let (_, st, container) = addition(p.seed, a);
    w.contents.push(label.clone());
    if !g.chance(0.1) {
        w.states.clear();
    }
    let held = [label.clone()];
    let mut ins = vec![before.as_obj(), obj(&label, &st, container)];
    if let Some(c) = container {
        if g.chance(0.6) {
            ins.push(Obj {
                label: c,
                states: &[],
                ingredients: &held,
                container: None,
            });
        }
    }
    if let Some((l, lst)) = w.inside.last() {
        if g.chance(0.4) {
            ins.push(obj(l, lst, Some(w.label)));
        }
    }
    if g.chance(0.2) {
        ins.push(obj(g.weighted(MIX_TOOLS), &[], None));
    }
    let empty = ["empty"];
    let mut outs = vec![w.obj()];
    let goes_inside = g.chance(0.85);
    if goes_inside {
        outs.push(obj(&label, &st, Some(w.label)));
    }
    if let Some(c) = container {
        if g.chance(0.25) {
            outs.push(obj(c, &empty, None));
        }
    }
    unit(buf, &ins, motion, &outs);
    if goes_inside {
        w.inside.push((label.clone(), st.clone()));
    }
}

/// The last unit: the dish is served and the working vessel comes back empty.
fn serve(g: &mut Rng, m: &Motions, w: &Vessel, buf: &mut Vec<u8>) -> ObjectSpec {
    let dish_label = if g.chance(0.7) {
        DISHES[g.below(DISHES.len())].to_owned()
    } else {
        format!("dish_{}", g.below(4096))
    };
    let plate = g.weighted(SERVING);
    let state = g.weighted(DISH_STATES);
    let motion = g.weighted(&m.add);
    let empty = ["empty"];
    let ds = [state];
    let dish = Obj {
        label: &dish_label,
        states: &ds,
        ingredients: &w.contents,
        container: Some(plate),
    };
    let mut outs = vec![dish];
    if g.chance(0.7) {
        outs.push(obj(w.label, &empty, None));
    }
    unit(buf, &[w.obj(), obj(plate, &empty, None)], motion, &outs);
    ObjectSpec {
        label: dish_label.clone(),
        states: vec![state.to_owned()],
        ingredients: w.contents.clone(),
        container: Some(plate.to_owned()),
    }
}

// ---------------------------------------------------------------- chunks

/// Writes chunk `c`: its share of the catalogue, then its recipes.
fn chunk(p: &Plan, m: &Motions, c: u64, chunks: u64) -> Vec<u8> {
    let mut buf = Vec::with_capacity(1 << 20);
    let items = p.main_items();
    let per = items.div_ceil(chunks.max(1));
    for x in (c * per).min(items)..((c + 1) * per).min(items) {
        catalogue_item(p, m, x, p.variants(x), &mut buf);
    }
    let end = ((c + 1) * CHUNK).min(p.recipes);
    for r in c * CHUNK..end {
        let len = if r + 1 == p.recipes {
            p.last_len
        } else {
            recipe_len(p.seed, r)
        };
        recipe(p, m, r, len, &mut buf);
    }
    buf
}

fn pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let mut b = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        b = b.num_threads(n.max(1));
    }
    b.build()
        .map_err(|e| Error::Invalid(format!("cannot start worker threads: {e}")))
}

/// Writes a FOON of `opts.units` units (course dialect) to `out`, streamed.
/// `progress(done, total)` is called after each batch of chunks (units written so far); it
/// returns false to stop (the result is then `Error::Cancelled`).
pub fn synth(
    opts: &SynthOptions,
    out: &mut dyn Write,
    progress: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<SynthReport> {
    let p = Plan::new(opts.seed, opts.units)?;
    let m = Motions::new();
    let chunks = p.recipes.div_ceil(CHUNK);
    let pool = pool(opts.threads)?;
    let batch = (pool.current_num_threads() as u64 * 2).max(2);
    let io = |e: std::io::Error| Error::Io {
        path: "<output>".into(),
        source: e,
    };
    let mut bytes = 0u64;
    let mut c = 0u64;
    let mut done = 0u64;
    while c < chunks {
        let to = (c + batch).min(chunks);
        let bufs: Vec<Vec<u8>> = pool.install(|| {
            (c..to)
                .into_par_iter()
                .map(|i| chunk(&p, &m, i, chunks))
                .collect()
        });
        for b in &bufs {
            out.write_all(b).map_err(io)?;
            bytes += b.len() as u64;
            done += memchr::memmem::find_iter(b, b"//\n").count() as u64;
        }
        c = to;
        if !progress(done.min(p.units), p.units) {
            return Err(Error::Cancelled);
        }
    }
    out.flush().map_err(io)?;
    Ok(SynthReport {
        units: p.units,
        bytes,
        recipes: p.recipes,
    })
}

/// As [`synth`], into `path`, atomically: the file appears whole or not at all (written
/// to a temporary file beside it, then renamed).
pub fn synth_to_path(
    opts: &SynthOptions,
    path: &Path,
    progress: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<SynthReport> {
    write_atomic(path, |w| synth(opts, w, progress))
}

/// Runs `f` on a writer into `path`, atomically (see [`crate::atomic`]).
pub fn write_atomic<T>(path: &Path, f: impl FnOnce(&mut dyn Write) -> Result<T>) -> Result<T> {
    crate::atomic::write_atomic(path, &[], f)
}

/// The kitchen of the FOON `synth` makes with these options: every raw object but the
/// withheld ingredients, in a fixed order.
pub fn synth_kitchen(opts: &SynthOptions) -> Result<Vec<ObjectSpec>> {
    let p = Plan::new(opts.seed, opts.units)?;
    let mut out = Vec::new();
    let spec = |label: &str, states: &[&str], container: Option<&str>| ObjectSpec {
        label: label.to_owned(),
        states: states.iter().map(|s| (*s).to_owned()).collect(),
        ingredients: Vec::new(),
        container: container.map(str::to_owned),
    };
    let mut vessels: Vec<&str> = VESSELS
        .iter()
        .chain(SERVING)
        .chain(SURFACES)
        .chain(RAW_CONTAINERS)
        .map(|v| v.0)
        .collect();
    vessels.sort_unstable();
    vessels.dedup();
    for v in vessels {
        out.push(spec(v, &["empty"], None));
    }
    let mut tools: Vec<&str> = PREP_TOOLS.iter().chain(MIX_TOOLS).map(|t| t.0).collect();
    tools.sort_unstable();
    tools.dedup();
    for t in tools {
        out.push(spec(t, &[], None));
    }
    for a in APPLIANCES {
        out.push(spec(a.0, &["off"], None));
    }
    let mut miss = Rng::new(p.seed, 8, 0);
    for x in 0..p.main_items() {
        let it = main_item(p.seed, Ok(x));
        if !miss.chance(KITCHEN_MISS) {
            out.push(spec(&it.label, &it.raw_states, it.raw_container));
        }
    }
    for a in 0..(ADDITIONS.len() as u64 + p.add_tail) {
        let (label, state, container) = addition(p.seed, a);
        if !miss.chance(KITCHEN_MISS) {
            out.push(spec(&label, &state, container));
            // The container it comes in, holding it (`packet {flour}`).
            if let Some(c) = container {
                out.push(ObjectSpec {
                    label: c.to_owned(),
                    states: Vec::new(),
                    ingredients: vec![label.clone()],
                    container: None,
                });
            }
        }
    }
    for r in 0..p.recipes {
        let it = main_item(p.seed, Err(r));
        if !miss.chance(KITCHEN_MISS) {
            out.push(spec(&it.label, &it.raw_states, it.raw_container));
        }
    }
    Ok(out)
}

/// Up to `count` goals: the dishes of recipes spread evenly over the FOON (recipes cut
/// short have none and are skipped).
pub fn synth_goals(opts: &SynthOptions, count: usize) -> Result<Vec<ObjectSpec>> {
    let p = Plan::new(opts.seed, opts.units)?;
    let m = Motions::new();
    let full = if p.last_len < recipe_len(p.seed, p.recipes - 1) {
        p.recipes - 1
    } else {
        p.recipes
    };
    let mut out = Vec::new();
    if full == 0 || count == 0 {
        return Ok(out);
    }
    let step = (full as f64 / count as f64).max(1.0);
    let mut seen = std::collections::BTreeSet::new();
    let mut buf = Vec::new();
    let mut i = 0f64;
    while (i as u64) < full && out.len() < count {
        let r = i as u64;
        i += step;
        if !seen.insert(r) {
            continue;
        }
        buf.clear();
        if let Some(d) = recipe(&p, &m, r, recipe_len(p.seed, r), &mut buf) {
            out.push(d);
        }
    }
    Ok(out)
}

/// The motion table of the generated FOONs: every course motion with its rate, as
/// `(motion, rate)` pairs.
pub fn synth_motions() -> Vec<(String, f64)> {
    MOTIONS.iter().map(|m| (m.0.to_owned(), m.2)).collect()
}

/// [`synth_motions`] in the `motion.txt` shape (`motion<TAB>rate` lines).
pub fn synth_motions_text() -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for (m, r) in synth_motions() {
        let _ = writeln!(s, "{m}\t{r:.2}");
    }
    s
}

/// One of the side files of a generation as text: `kitchen` (JSON), `goals` (JSON, up to
/// `count`) or `motions` (the rate table).
pub fn synth_side_text(opts: &SynthOptions, what: &str, count: usize) -> Result<String> {
    match what {
        "kitchen" => crate::write::json::objects_json(&synth_kitchen(opts)?),
        "goals" => crate::write::json::objects_json(&synth_goals(opts, count)?),
        "motions" => Ok(synth_motions_text()),
        _ => Err(Error::Invalid(format!(
            "unknown synth output '{what}' (choose from kitchen, goals, motions)"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(units: u64, seed: u64, threads: Option<usize>) -> Vec<u8> {
        let mut out = Vec::new();
        synth(
            &SynthOptions {
                units,
                seed,
                threads,
            },
            &mut out,
            &mut |_, _| true,
        )
        .unwrap();
        out
    }

    #[test]
    fn exact_count_no_duplicates_and_deterministic() {
        for units in [1, 2, 3, 7, 50, 600, 3000] {
            let a = text(units, 4, Some(1));
            assert_eq!(a, text(units, 4, Some(2)));
            let foon = crate::parse_foon(&a, None, crate::ParseOptions::default()).unwrap();
            assert_eq!(foon.fu_count() as u64, units, "units {units}");
            assert!(foon.warnings().is_empty(), "{:?}", foon.warnings().first());
        }
        assert_ne!(text(500, 1, None), text(500, 2, None));
    }

    #[test]
    fn catalogue_variants_are_distinct_by_construction() {
        let m = Motions::new();
        assert!(MAX_VARIANTS <= 2 * m.prepare.len() as u64 * PREP_TOOLS.len() as u64);
    }

    #[test]
    fn bounds() {
        let mut sink = Vec::new();
        for units in [0, MAX_UNITS + 1] {
            let o = SynthOptions {
                units,
                seed: 0,
                threads: None,
            };
            assert!(matches!(
                synth(&o, &mut sink, &mut |_, _| true),
                Err(Error::Invalid(_))
            ));
        }
    }
}

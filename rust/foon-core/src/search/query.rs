//! The vocabulary of a planning call: the [`Method`], the [`Compat`]ibility, how
//! `greedy-inputs` [`Count`]s inputs, and the [`Query`] that holds them.

use std::str::FromStr;

use crate::error::{Error, Result};
use crate::prepare::Objective;

/// A planning method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    Bfs,
    Ids,
    GreedySuccess,
    GreedyInputs,
    OptimalSuccess,
    OptimalUnits,
    OptimalInputs,
    OptimalShared,
}

impl Method {
    pub const ALL: [Method; 8] = [
        Self::Bfs,
        Self::Ids,
        Self::GreedySuccess,
        Self::GreedyInputs,
        Self::OptimalSuccess,
        Self::OptimalUnits,
        Self::OptimalInputs,
        Self::OptimalShared,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Bfs => "bfs",
            Self::Ids => "ids",
            Self::GreedySuccess => "greedy-success",
            Self::GreedyInputs => "greedy-inputs",
            Self::OptimalSuccess => "optimal-success",
            Self::OptimalUnits => "optimal-units",
            Self::OptimalInputs => "optimal-inputs",
            Self::OptimalShared => "optimal-shared",
        }
    }

    /// The objective whose per-kitchen optimum sound plans of this optimal method read
    /// (`optimal-shared` reads those of the methods it bounds with: `search::shared`).
    pub(crate) fn objective(self) -> Option<Objective> {
        match self {
            Self::OptimalSuccess => Some(Objective::Success),
            Self::OptimalUnits => Some(Objective::Units),
            Self::OptimalInputs => Some(Objective::Inputs),
            _ => None,
        }
    }

    /// Whether this method needs motion rates to choose.
    pub fn uses_rates(self) -> bool {
        matches!(self, Self::GreedySuccess | Self::OptimalSuccess)
    }
}

impl FromStr for Method {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.as_str() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|m| m.as_str()).collect();
                Error::Invalid(format!(
                    "unknown method '{s}' (choose from {})",
                    names.join(", ")
                ))
            })
    }
}

/// Which semantics: the course code's, or sound (always executable) trees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Compat {
    #[default]
    Sound,
    Course,
}

impl Compat {
    /// The name results report (`"sound"` or `"course"`), which [`FromStr`] reads back.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Sound => "sound",
            Self::Course => "course",
        }
    }
}

impl FromStr for Compat {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "sound" | "none" => Ok(Self::Sound),
            "course" => Ok(Self::Course),
            _ => Err(Error::Invalid(format!(
                "unknown compatibility '{s}' (choose from course, sound)"
            ))),
        }
    }
}

/// How `greedy-inputs` counts the inputs of an FU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Count {
    #[default]
    Nodes,
    Ingredients,
}

impl Count {
    /// The name results report (`"nodes"` or `"ingredients"`), which [`FromStr`] reads back.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Nodes => "nodes",
            Self::Ingredients => "ingredients",
        }
    }
}

impl FromStr for Count {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "nodes" => Ok(Self::Nodes),
            "ingredients" => Ok(Self::Ingredients),
            _ => Err(Error::Invalid(format!(
                "unknown count '{s}' (choose from nodes, ingredients)"
            ))),
        }
    }
}

/// Options of one planning call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Query {
    pub method: Method,
    pub compat: Compat,
    pub count: Count,
}

impl Default for Query {
    fn default() -> Self {
        Self {
            method: Method::Ids,
            compat: Compat::Sound,
            count: Count::Nodes,
        }
    }
}

impl Query {
    /// Whether the method has the form asked for: the optimal methods have no
    /// course-compatible form (`bfs` is the course loop whatever is asked).
    pub fn check(&self) -> crate::error::Result<()> {
        match (self.compat, self.method) {
            (
                Compat::Course,
                Method::OptimalSuccess
                | Method::OptimalUnits
                | Method::OptimalInputs
                | Method::OptimalShared,
            ) => Err(crate::error::Error::Invalid(format!(
                "method {} has no course-compatible form",
                self.method.as_str()
            ))),
            _ => Ok(()),
        }
    }
}

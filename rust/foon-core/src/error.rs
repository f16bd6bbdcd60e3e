//! One error model for the whole crate: every failure on user data is a typed [`Error`]
//! that names the file, line and column where it applies.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in an input something was found: a file (or `<string>`), a 1-based line and a
/// 1-based column counted in characters.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub path: Option<PathBuf>,
    pub line: u64,
    pub column: u32,
}

impl Location {
    pub fn new(path: Option<&Path>, line: u64, column: u32) -> Self {
        Self {
            path: path.map(Path::to_path_buf),
            line,
            column,
        }
    }

    /// The file name as shown to users: the path, or `<string>` for in-memory text.
    pub fn source_name(&self) -> String {
        self.path
            .as_ref()
            .map_or_else(|| "<string>".to_owned(), |p| p.display().to_string())
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.source_name(), self.line, self.column)
    }
}

/// What kind of input a parse error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    Foon,
    Kitchen,
    Goal,
    Motions,
    Utensils,
    Tree,
    RateOverrides,
}

impl InputKind {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Foon => "FOON",
            Self::Kitchen => "kitchen",
            Self::Goal => "goal",
            Self::Motions => "motion table",
            Self::Utensils => "utensil list",
            Self::Tree => "task tree",
            Self::RateOverrides => "rate override file",
        }
    }
}

/// Every error the core can return.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// Malformed input: file, line, column and a short reason.
    Parse {
        at: Location,
        kind: InputKind,
        reason: String,
    },
    /// The file could not be read.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The goal is not an object of the FOON: the goal, described, and the objects most
    /// similar to it (at most [`find::SUGGESTED`](crate::find::SUGGESTED), described, best
    /// first; see [`find::goal_not_found`](crate::find::goal_not_found)).
    GoalNotFound { goal: String, nearest: Vec<String> },
    /// A goal given by its label only, which several objects have: the label, how many
    /// objects have it, and the first few of them, described.
    GoalAmbiguous {
        label: String,
        count: usize,
        shown: Vec<String>,
    },
    /// A motion used by a candidate FU has no success rate and no default was given.
    MissingRate { motion: String },
    /// A bad argument (unknown method name, rate out of range, ...).
    Invalid(String),
    /// Work was cancelled through its stop flag.
    Cancelled,
    /// An output could not be written: Graphviz's `dot` is missing or failed, or the graph
    /// is too large to draw.
    Output(String),
    /// A count or offset of the index would pass what its columns hold: `what` names it
    /// ("input edges", "string bytes"), `limit` is the largest count allowed.
    TooLarge { what: &'static str, limit: u64 },
    /// An index file (`.foonidx`) that cannot be opened: corrupt, truncated, of another format
    /// version, or written for another byte order. `reason` says what is wrong, naming the
    /// column and byte offsets where they apply.
    BadIndex { path: PathBuf, reason: String },
}

impl Error {
    pub fn parse(
        kind: InputKind,
        path: Option<&Path>,
        line: u64,
        column: u32,
        reason: impl Into<String>,
    ) -> Self {
        Self::Parse {
            at: Location::new(path, line, column),
            kind,
            reason: reason.into(),
        }
    }

    pub fn io(path: &Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// `n` as a new `u32` id (the count of `what` before it is added), or
    /// [`Error::TooLarge`] naming `what` when it does not fit below [`u32::MAX`] (which id
    /// columns keep for "no value"): at most 4294967295 of anything.
    pub fn check_id(n: usize, what: &'static str) -> Result<u32> {
        u32::try_from(n)
            .ok()
            .filter(|&v| v < u32::MAX)
            .ok_or(Self::TooLarge {
                what,
                limit: u64::from(u32::MAX),
            })
    }

    /// `n` as a `u32` offset (the length of a column of `what`, at most [`u32::MAX`]), or
    /// [`Error::TooLarge`] naming `what`.
    pub fn check_offset(n: usize, what: &'static str) -> Result<u32> {
        u32::try_from(n).map_err(|_| Self::TooLarge {
            what,
            limit: u64::from(u32::MAX),
        })
    }

    /// The location of a parse error, if this is one.
    pub fn location(&self) -> Option<&Location> {
        match self {
            Self::Parse { at, .. } => Some(at),
            _ => None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Parse { at, kind, reason } => {
                write!(f, "{at}: {} error: {reason}", kind.as_str())
            }
            Self::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Self::GoalNotFound { goal, nearest } => {
                write!(f, "The goal node does not exist: {goal}")?;
                if !nearest.is_empty() {
                    write!(f, "; nearest: {}", nearest.join("; "))?;
                }
                Ok(())
            }
            Self::GoalAmbiguous {
                label,
                count,
                shown,
            } => {
                write!(
                    f,
                    "the label '{label}' matches {count} objects: {}",
                    shown.join("; ")
                )?;
                if *count > shown.len() {
                    write!(f, "; and {} more", count - shown.len())?;
                }
                f.write_str(" \u{2014} give the goal as JSON to choose one")
            }
            Self::MissingRate { motion } => write!(
                f,
                "motion '{motion}' has no success rate in the motion table \
                 (give a default rate to use one)"
            ),
            Self::Invalid(msg) | Self::Output(msg) => f.write_str(msg),
            Self::Cancelled => f.write_str("cancelled"),
            Self::TooLarge { what, limit } => {
                write!(f, "too large: more than {limit} {what}")
            }
            Self::BadIndex { path, reason } => write!(f, "{}: {reason}", path.display()),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// A problem that does not stop loading (an FU dropped for an annotation fault, ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    pub at: Location,
    pub kind: WarningKind,
    pub message: String,
}

/// The kinds of [`Warning`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WarningKind {
    /// An FU without a motion line; it is dropped.
    NoMotion,
    /// An FU with two motion lines; it is dropped.
    TwoMotions,
    /// The last FU has no closing `//`; it is kept.
    Unterminated,
    /// Lint note: an ingredient with leading or trailing spaces (`{a, b}`).
    SpacedIngredient,
    /// Lint note: the same ingredient twice in one list.
    DuplicateIngredient,
    /// Lint note: `[]`, an empty container name.
    EmptyContainer,
    /// A second container line on one object; the last one wins (course rule).
    TwoContainers,
    /// A second ingredient list on one object; the last one wins (course rule).
    TwoIngredientLists,
    /// An empty item in an ingredient list (`{}`, `{a,}`); kept as the ingredient `''`, as
    /// the course parser does.
    EmptyIngredient,
}

impl WarningKind {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::NoMotion => "no-motion",
            Self::TwoMotions => "two-motions",
            Self::Unterminated => "unterminated",
            Self::SpacedIngredient => "spaced-ingredient",
            Self::DuplicateIngredient => "duplicate-ingredient",
            Self::EmptyContainer => "empty-container",
            Self::TwoContainers => "two-containers",
            Self::TwoIngredientLists => "two-ingredient-lists",
            Self::EmptyIngredient => "empty-ingredient",
        }
    }

    /// What loading does about a fault of this kind (the end of its warning message), for the
    /// kinds that strict mode turns into errors; `None` for lint notes, which it ignores.
    pub fn consequence(self) -> Option<&'static str> {
        match self {
            Self::NoMotion | Self::TwoMotions => Some("it is dropped"),
            Self::Unterminated => Some("it is kept"),
            Self::TwoContainers | Self::TwoIngredientLists => Some("the last one wins"),
            Self::EmptyIngredient => Some("it is kept as the ingredient '' (course rule)"),
            Self::SpacedIngredient | Self::DuplicateIngredient | Self::EmptyContainer => None,
        }
    }

    /// Whether a warning of this kind is a load warning ([`crate::Foon::warnings`]: a unit
    /// dropped or kept unterminated); the other kinds are found by `foon check`
    /// ([`crate::Foon::notes`]).
    pub fn is_load_warning(self) -> bool {
        matches!(self, Self::NoMotion | Self::TwoMotions | Self::Unterminated)
    }
}

impl Warning {
    /// The warning for `fault` (what is wrong), ending with what loading does about it.
    /// Strict mode reports the same fault as an error: "`fault` (strict mode)".
    pub fn fault(at: Location, kind: WarningKind, fault: &str) -> Self {
        let message = match kind.consequence() {
            Some(c) => format!("{fault}; {c}"),
            None => fault.to_owned(),
        };
        Self { at, kind, message }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: warning: {} [{}]",
            self.at,
            self.message,
            self.kind.as_str()
        )
    }
}

//! What a dialect is, seen from the machine layer: its names, files, vocabulary, settings,
//! examples and syntax colours ([`DialectInfo`]). Each dialect's folder describes itself with one
//! `dialect::DIALECT` value and a `dialect::open` that assembles a program into its machine; the
//! list of dialects and the glue that makes a debugger engine of a machine are the composition
//! root's (`crate::registry`), above the layers.

use std::collections::BTreeMap;
use std::path::Path;

use crate::machine::project::Project;

/// A dialect's settings by key (SilverLode: the servo model). Stored in sessions.
pub type Settings = BTreeMap<String, f64>;

/// The class of a piece of program text, for the code view's colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TokenClass {
    Plain,
    Mnemonic,
    Operation,
    Number,
    Location,
    Label,
    Comment,
    Condition,
}

/// Colour classes of one line of whitespace-separated words (the instruction-list dialects):
/// from the character where `comment_starts(chars, i, first_word)` holds to the end is a
/// comment; `separates` splits words besides whitespace; `class_of(word, first_word)` gives each
/// word's class (the word upper-cased).
pub fn classify_words(
    line: &str,
    comment_starts: impl Fn(&[char], usize, bool) -> bool,
    separates: impl Fn(char) -> bool,
    class_of: impl Fn(&str, bool) -> TokenClass,
) -> Vec<TokenClass> {
    let chars: Vec<char> = line.chars().collect();
    let mut kinds = vec![TokenClass::Plain; chars.len()];
    let mut i = 0;
    let mut first = true;
    while i < chars.len() {
        if comment_starts(&chars, i, first) {
            kinds[i..].fill(TokenClass::Comment);
            break;
        }
        if chars[i].is_whitespace() || separates(chars[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len()
            && !chars[i].is_whitespace()
            && !separates(chars[i])
            && !comment_starts(&chars, i, false)
        {
            i += 1;
        }
        let word = chars[start..i]
            .iter()
            .collect::<String>()
            .to_ascii_uppercase();
        kinds[start..i].fill(class_of(&word, first));
        first = false;
    }
    kinds
}

/// The words a dialect's users use for its units of time and work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Vocabulary {
    /// "tick" or "scan".
    pub tick: &'static str,
    pub ticks: &'static str,
    /// "command", "statement" or "instruction".
    pub step: &'static str,
    pub steps: &'static str,
    /// Hints in the dialect's own names for the fields that take them: a location, an
    /// expression to watch (examples separated by ", ") and a breakpoint condition.
    pub location_hint: &'static str,
    pub watch_hint: &'static str,
    pub condition_hint: &'static str,
}

/// One setting of a dialect's model, with its stable range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettingInfo {
    pub key: &'static str,
    pub label: &'static str,
    pub help: &'static str,
    pub min: f64,
    pub max: f64,
    pub default: f64,
    /// Whole numbers only.
    pub integer: bool,
}

/// A default plot channel: a location name and how the legend calls it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChannelSpec {
    pub location: &'static str,
    pub label: &'static str,
    /// Channels of the same group share a plot; groups are stacked.
    pub group: u8,
}

/// What the runner does when the tick limit comes first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AtLimit {
    /// Status `limit`, exit 3 (programs that end by themselves).
    Limit,
    /// Status `ended`, exit 0 (scanned PLCs: running N scans is the whole job).
    Ended,
}

/// A dialect as the machine layer describes it.
pub struct DialectInfo {
    /// Identifier used in sessions, `--dialect` and the runner's JSON.
    pub name: &'static str,
    pub display_name: &'static str,
    /// File name extensions without the dot, lower case; the first is the one new files get.
    pub extensions: &'static [&'static str],
    pub vocabulary: Vocabulary,
    /// Built-in example programs: (file name, text).
    pub examples: &'static [(&'static str, &'static str)],
    /// Built-in example programs of several files: each a title (its folder) and a list of
    /// (file name, text), the top file first.
    #[allow(clippy::type_complexity)]
    pub projects: &'static [(&'static str, &'static [(&'static str, &'static str)])],
    /// Lesson sessions shipped in `sessions/`: (file name, text).
    pub lessons: &'static [(&'static str, &'static str)],
    /// The user's reference, `docs/<dialect>.md`: its `## Instruction reference` section gives
    /// the hover text and the Help panel of each mnemonic ([`crate::machine::reference`]).
    pub reference: &'static str,
    /// Every mnemonic the assembler accepts, in the assembler's own lists (each must have a
    /// reference entry).
    pub mnemonics: &'static [&'static [&'static str]],
    pub settings: &'static [SettingInfo],
    pub default_channels: &'static [ChannelSpec],
    /// The runner's `--max-ticks` default.
    pub default_max_ticks: u64,
    pub at_limit: AtLimit,
    /// A starting text for File → New.
    pub new_program: &'static str,
    /// The shortest text that assembles to a program doing nothing: what the debugger stands on
    /// while the user's text does not assemble ("" for most; DL205 requires END).
    pub empty_program: &'static str,
    /// The error flags "break on error" watches ([`crate::machine::MachineView::error_lamp`]),
    /// as the checkbox names them.
    pub error_flags: &'static str,
    /// A number with a point (`1.5`) is a 16.16 fixed-point literal (TML): hovering one shows
    /// what it really stores.
    pub decimal_literals_are_fixed: bool,
    /// The paths a file's text includes (TML's `#include`), for loading a project from disk.
    pub includes: Option<fn(text: &str) -> Vec<String>>,
    /// Colour class of every character of one line (without its newline).
    pub classify: fn(line: &str) -> Vec<TokenClass>,
}

impl DialectInfo {
    /// Read the program whose top file is `path`, with its included files from its own folder
    /// and below.
    pub fn load(&self, path: &Path) -> Result<Project, crate::text::TextError> {
        self.load_with(path, &crate::machine::project::IncludeFolders::default())
    }

    /// Read the program whose top file is `path`, with its included files from its own folder
    /// and below and from the folders `folders` allows.
    pub fn load_with(
        &self,
        path: &Path,
        folders: &crate::machine::project::IncludeFolders,
    ) -> Result<Project, crate::text::TextError> {
        match self.includes {
            Some(includes) => crate::machine::project::load(path, includes, folders),
            None => {
                let text = crate::text::read(path)?;
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                Ok(Project::single(name, text))
            }
        }
    }

    /// Whether `word` is one of the dialect's mnemonics (case-insensitive).
    pub fn is_mnemonic(&self, word: &str) -> bool {
        self.mnemonics
            .iter()
            .flat_map(|list| list.iter())
            .any(|m| m.eq_ignore_ascii_case(word))
    }

    /// The reference entry of `mnemonic`, if it is one of the dialect's.
    pub fn reference_entry(&self, mnemonic: &str) -> Option<crate::machine::reference::Entry> {
        if !self.is_mnemonic(mnemonic) {
            return None;
        }
        crate::machine::reference::entry_for(self.reference, mnemonic)
    }

    /// The settings with every key at its default, overridden by `given` where it has a
    /// value for a known key, each brought into its range (NaN becomes the default).
    pub fn settings_from(&self, given: &Settings) -> Settings {
        self.settings
            .iter()
            .map(|s| {
                let v = given.get(s.key).copied().unwrap_or(s.default);
                let v = if v.is_nan() {
                    s.default
                } else {
                    v.clamp(s.min, s.max)
                };
                let v = if s.integer { v.round() } else { v };
                (s.key.to_string(), v)
            })
            .collect()
    }

    pub fn default_settings(&self) -> Settings {
        self.settings_from(&Settings::new())
    }

    /// One `KEY=VALUE` of the runner's `--setting`: a key this dialect has and a value in its
    /// range (whole when the setting is). Out of range is an error here, not clamped: a
    /// script asking for 5000 ms scans must hear it got something else.
    pub fn parse_setting(&self, text: &str) -> Result<(String, f64), String> {
        let Some((key, value)) = text.split_once('=') else {
            return Err(format!("--setting {text}: expected KEY=VALUE"));
        };
        let (key, value) = (key.trim(), value.trim());
        let known = || {
            let keys: Vec<&str> = self.settings.iter().map(|s| s.key).collect();
            if keys.is_empty() {
                format!("{} has no settings", self.display_name)
            } else {
                format!("{} settings: {}", self.display_name, keys.join(", "))
            }
        };
        let Some(info) = self.settings.iter().find(|s| s.key == key) else {
            return Err(format!("--setting {key}: no such setting ({})", known()));
        };
        let number: f64 = value
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| format!("--setting {key}={value}: not a number"))?;
        if info.integer && number.fract() != 0.0 {
            return Err(format!("--setting {key}={value}: a whole number is needed"));
        }
        if number < info.min || number > info.max {
            return Err(format!(
                "--setting {key}={value}: out of range ({}–{})",
                info.min, info.max
            ));
        }
        Ok((key.to_string(), number))
    }
}

impl std::fmt::Debug for DialectInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Dialect").field("name", &self.name).finish()
    }
}

impl PartialEq for DialectInfo {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

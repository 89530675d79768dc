//! Preferences kept between runs by eframe's storage.

use super::*;

/// Preferences kept between runs by eframe's storage (never the program state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub dark: bool,
    pub recent: Vec<PathBuf>,
    /// The run speed the user chose, per dialect; a dialect not listed runs in real time (a
    /// 12 s traffic light at 10 instructions/s looked frozen).
    pub speeds: BTreeMap<String, Speed>,
    /// The register view's format per dialect, where the user chose one for every location.
    pub register_formats: BTreeMap<String, Format>,
    pub only_used_registers: bool,
    /// The panel layout as the user left it; `None` for the default.
    #[serde(with = "layout::as_text")]
    pub layout: Option<layout::Layout>,
    /// The titles of the panels the build had when `layout` was saved: a panel added since
    /// then joins a saved layout once, while one the user closed stays closed. Plain text, so
    /// a damaged entry costs nothing.
    #[serde(default = "layout::panes_before_debugger_panels")]
    pub known_panes: Vec<String>,
    /// Folders besides a program's own that its `#include`d files may be read from (the
    /// runner's `--include-dir`); none unless the user adds them.
    pub include_folders: Vec<PathBuf>,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            dark: true,
            recent: Vec::new(),
            speeds: BTreeMap::new(),
            register_formats: BTreeMap::new(),
            only_used_registers: true,
            layout: None,
            known_panes: layout::Pane::common_titles(),
            include_folders: Vec::new(),
        }
    }
}

impl Prefs {
    /// Where included files may be read from, besides the program's own folder.
    pub fn include_folders(&self) -> servoscope_core::machine::project::IncludeFolders {
        servoscope_core::machine::project::IncludeFolders {
            allowed: self.include_folders.clone(),
        }
    }

    /// The speed a program of `dialect` starts at: the user's last choice for it, else real
    /// time.
    pub fn speed_for(&self, dialect: &str) -> Speed {
        self.speeds
            .get(dialect)
            .copied()
            .unwrap_or(Speed::RealTime(1.0))
    }
}

pub const PREFS_KEY: &str = "servoscope-prefs";
pub(super) const MAX_RECENT: usize = 10;

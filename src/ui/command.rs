//! What the window's panels, menus and keys ask for.

use super::*;

/// What a user asked for, from a panel, the menu or a key: an action of the debugger's, or one
/// of the window's own (files, dialogs, layout, lessons).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    Debug(Action),
    EditSource(String),
    /// Show each statement's program-memory address in the code view's gutter.
    ShowAddresses(bool),
    /// A tab double-clicked: fill the window with it, or back to the layout.
    ToggleMaximise(egui_tiles::TileId),
    /// The text of file `.0` of the program (0 is the top file) was edited.
    EditFile(usize, String),
    OpenDialog,
    /// Open a program or a session (asks first when there are unsaved changes).
    OpenPath(PathBuf),
    /// Ctrl+S: save to the current session file, or ask where.
    SaveSession,
    SaveSessionDialog,
    SaveSessionTo(PathBuf),
    /// Save the program text to its file, or ask where.
    SaveProgram,
    SaveProgramDialog,
    SaveProgramTo(PathBuf),
    /// Save over a file that is not a session, after the user confirmed.
    SaveSessionOver(PathBuf),
    /// Go on with the action waiting behind "unsaved changes".
    DiscardAndContinue,
    CancelPending,
    ExportDialog,
    ExportCsv(PathBuf),
    /// An example of any dialect, by its index in [`registry::examples`].
    LoadExample(usize),
    /// An example of several files, by its index in [`registry::example_projects`].
    LoadExampleProject(usize),
    /// A lesson session of any dialect, by its index in [`registry::lessons`].
    LoadLesson(usize),
    /// File -> New: an empty program in the dialect with this name.
    NewProgram(&'static str),
    SetDark(bool),
    OpenSettings,
    /// View → Include folders…
    OpenIncludeFolders,
    /// Let included files be read from this folder too (kept in the preferences).
    AllowIncludeFolder(PathBuf),
    ForbidIncludeFolder(PathBuf),
    SetSettings(Settings),
    /// Close (false) or reopen (true) a panel.
    ShowPane(layout::Pane, bool),
    ResetLayout,
    AddBreakpoint(Breakpoint),
    /// Go back to the write of this location (again: the write before).
    WhoWrote(Loc),
    AddWatch(String),
    PlotWatch(usize),
    /// Scroll the program to a line and put the caret there.
    ShowLine(usize),
    ExportLogDialog,
    ExportLog(PathBuf),
    /// Show a location in the register view.
    SelectLocation(Loc),
    /// Bring a panel's tab to the front.
    FocusPane(layout::Pane),
    ExportLadderDialog,
    ExportLadder(PathBuf),
    /// F1 / Help → Reference: the Help panel at this mnemonic's entry (the whole reference
    /// without one).
    OpenHelp(Option<String>),
    /// Show this step of the open lesson (from 0).
    LessonStep(usize),
    /// Evaluate the shown step's checks on the present state.
    LessonCheck,
    /// Back to the lesson's program and position.
    LessonReset,
    /// File → Save as lesson: this session becomes a lesson to write, then to save.
    SaveAsLesson,
}

impl From<Action> for Command {
    fn from(action: Action) -> Self {
        Command::Debug(action)
    }
}

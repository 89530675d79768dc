//! The program: loading one (of one file or several, in any dialect), assembling it, and
//! the new timeline each assembly or restart begins.

use super::history::UserEvent;
use super::{
    BreakKind, ChannelChoice, Debugger, Dialect, Event, FIRST_CHUNK_TICKS, Project, Settings,
};
use super::{empty_engine, lines, next_generation, normalized};

impl Debugger {
    // ---- program ---------------------------------------------------------------------------

    /// Replace the whole program (File -> Open). Breakpoints are cleared.
    pub fn load(&mut self, name: impl Into<String>, source: impl Into<String>) {
        let dialect = self.dialect;
        self.load_as(dialect, name, source);
    }

    /// Replace the whole program with one of several files (File -> Open of a top file).
    pub fn load_project(&mut self, dialect: &'static Dialect, project: Project) {
        let name = project.top_name().to_string();
        self.load_as(dialect, name, "");
        self.project = normalized(project);
        self.assemble();
        self.assembled = self.project.clone();
    }

    /// Replace the whole program with one in `dialect`. Breakpoints are cleared; the settings
    /// and plot channels become the dialect's defaults when the dialect changes.
    pub fn load_as(
        &mut self,
        dialect: &'static Dialect,
        name: impl Into<String>,
        source: impl Into<String>,
    ) {
        if dialect != self.dialect {
            self.dialect = dialect;
            self.settings = dialect.default_settings();
        }
        // The last program's channels are not this one's: it starts on what it uses.
        self.channel_names = ChannelChoice::defaults(dialect);
        // Nothing of the previous program stays: not its state, its history, nor its inputs
        // (a new program starts with every input low, as the runner does).
        self.engine = empty_engine(dialect, &self.settings);
        self.name = name.into();
        self.project = Project::single(
            self.name.clone(),
            crate::text::normalize(&source.into()).into_owned(),
        );
        self.assembled = Project::default();
        // Breakpoints and watches belong to their program: a new one starts clean.
        self.breaks.clear();
        self.watches.clear();
        self.assemble();
        // The text is as loaded, not edited, even when it does not assemble.
        self.assembled = self.project.clone();
        self.channels_for_program();
    }

    /// A new timeline at the start of the current program: every input low, as in the runner
    /// (a run's input switches are part of its recorded timeline, not of the next run).
    pub(super) fn restart(&mut self) {
        let channels = self.resolve_channels(self.engine.machine());
        let m = self.engine.machine();
        let events = self
            .scripted
            .iter()
            .filter_map(|e| {
                let loc = m.find(&e.location)?;
                // An edit this program's location cannot take is left out, like an unknown name.
                e.change.check(&m.info(loc)?).ok()?;
                Some(UserEvent {
                    at: e.at,
                    loc,
                    change: e.change,
                })
            })
            .collect();
        self.engine = self.engine.restarted(events, channels);
        self.goal = None;
        self.chunk_ticks = FIRST_CHUNK_TICKS;
        self.chunk_floor = None;
        self.last_writer = None;
        self.generation = next_generation();
        self.rebuild_checker(false);
    }

    /// Assemble the current text. On success the machine restarts on the new program and
    /// breakpoints follow the lines they were on; on failure the diagnostics are kept and the
    /// old state stays on screen, but nothing runs.
    pub fn assemble(&mut self) -> bool {
        self.goal = None;
        match self.dialect.open_program(&self.project, &self.settings) {
            Ok(engine) => {
                // Each file's breakpoints follow their lines in that file's edit.
                let movers: Vec<_> = (0..self.project.files.len())
                    .map(|f| {
                        let old = self.assembled.files.get(f).map_or("", |x| x.text.as_str());
                        lines::line_mover(old, &self.project.files[f].text)
                    })
                    .collect();
                self.breaks.retain_mut(|b| match &mut b.kind {
                    BreakKind::Line(l) => {
                        let (file, local) = Project::split(*l);
                        movers
                            .get(file)
                            .and_then(|moved| moved(local))
                            .map(|to| *l = Project::line(file, to))
                            .is_some()
                    }
                    BreakKind::Data { .. } => true,
                });
                self.engine = engine;
                self.restart();
                self.assembled = self.project.clone();
                // What is left are warnings: they are shown, the program runs.
                self.diagnostics = self.engine.machine().warnings();
                self.diagnostics.sort_by_key(|d| (d.line, d.col));
                self.event = Some(Event::Assembled);
                true
            }
            Err(mut diagnostics) => {
                // Views find a line's diagnostics by binary search.
                diagnostics.sort_by_key(|d| (d.line, d.col));
                self.event = Some(Event::NotAssembled(diagnostics.len()));
                self.diagnostics = diagnostics;
                false
            }
        }
    }

    /// Assemble first if the text changed. False when the program cannot run.
    pub(super) fn ready(&mut self) -> bool {
        if self.is_edited() || self.has_errors() {
            return self.assemble();
        }
        true
    }

    /// The dialect's settings; applying them restarts the program.
    pub fn set_settings(&mut self, settings: &Settings) {
        self.settings = self.dialect.settings_from(settings);
        self.assembled = Project::default();
        self.assemble();
    }
}

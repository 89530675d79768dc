//! Drawing the window each frame: menus, panels, dialogs and prompts.

use super::*;

impl ServoscopeApp {
    /// One frame: keys, the run slice, then every panel. Usable without eframe (tests).
    pub fn show(&mut self, ui: &mut egui::Ui) {
        if !self.fonts_installed {
            // Fonts change from the next pass on: this one is thrown away unseen.
            theme::install_fonts(ui.ctx());
            self.fonts_installed = true;
            ui.ctx().request_discard("the fonts were installed");
            ui.ctx().request_repaint();
            return;
        }
        let ctx = ui.ctx().clone();
        if self.ctx.is_none() {
            self.ctx = Some(ctx.clone());
        }
        if let Some(lesson) = &mut self.lesson {
            lesson.poll();
        }
        // Which files differ from what was opened or saved: their tabs carry a •.
        let saved = self.file_text.as_deref().unwrap_or_default();
        self.code.unsaved = self
            .debugger
            .project()
            .files
            .iter()
            .enumerate()
            .map(|(k, f)| saved.get(k) != Some(&f.text))
            .collect();
        if self.theme_applied != Some(self.prefs.dark) {
            theme::apply(&ctx, self.prefs.dark);
            self.theme_applied = Some(self.prefs.dark);
        }

        // Closing with unsaved changes asks first.
        if ctx.input(|i| i.viewport().close_requested()) && !self.allow_close && self.is_dirty() {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.pending = Some(Pending::Quit);
        }
        if self.allow_close && self.pending.is_none() && self.frame_stats.is_none() {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }

        self.poll_loading(&ctx);
        let mut commands = Vec::new();
        // Keys are taken now (before a widget sees them) but acted on at the end of the frame,
        // after the editor's text of this same frame: Ctrl+Enter right after a keystroke
        // assembles the text on screen.
        let mut keyed = Vec::new();
        controls::shortcuts(&ctx, &self.debugger, &self.code, &mut keyed);
        files::dropped_files(&ctx, &mut commands);
        self.files.poll(&mut commands);
        if self.loading.is_some() {
            commands.clear();
        }
        for c in commands.drain(..) {
            self.apply(&ctx, c);
        }

        let now = Instant::now();
        let interval = self.last_frame.map(|t| now.duration_since(t));
        self.last_frame = Some(now);
        if let Some(interval) = interval
            && self.debugger.is_running()
        {
            let overhead = interval.saturating_sub(self.last_slice);
            self.overhead = (self.overhead * 7 + overhead) / 8;
        }
        let slice = run_slice(self.overhead);
        let dt = interval.map_or(0.0, |d| d.as_secs_f64());
        let sim_start = Instant::now();
        self.debugger.advance(dt, slice);
        self.last_slice = sim_start.elapsed();

        // The window is cleared to the panels' colour (`clear_color`), so the panels paint no
        // fill: without a GPU every filled pixel is shaded in software, and the central panel's
        // fill alone was more than all the rest of a frame's drawing together.
        let bar = egui::Frame::side_top_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        let central = egui::Frame::central_panel(ui.style()).fill(egui::Color32::TRANSPARENT);
        egui::Panel::top("menu").frame(bar).show(ui, |ui| {
            controls::menu_bar(ui, self, &mut commands);
            controls::toolbar(
                ui,
                &self.debugger,
                &mut self.extra_inputs,
                &mut self.new_input,
                &mut commands,
            );
        });
        egui::Panel::bottom("status_bar").frame(bar).show(ui, |ui| {
            status::status_bar(ui, &self.debugger);
        });
        egui::CentralPanel::default().frame(central).show(ui, |ui| {
            if let Some(notice) = self.notice.clone()
                && status::notice_banner(ui, &notice)
            {
                self.notice = None;
            }
            status::fault_banner(ui, &self.debugger);
            for panel in &self.panels {
                let pane = layout::Pane::Dialect(panel.title().to_string());
                self.layout
                    .show_when(&pane, panel.has_content(&self.debugger));
            }
            // A program just opened: bring forward the panel that suits it best (the last
            // registered that asks).
            // An open lesson keeps its tab in front: it is what the student reads first.
            if std::mem::take(&mut self.focus_panel_pending)
                && self.lesson.is_none()
                && let Some(panel) = self
                    .panels
                    .iter()
                    .rev()
                    .find(|p| p.wants_focus(&self.debugger))
            {
                self.layout
                    .focus(&layout::Pane::Dialect(panel.title().to_string()));
            }
            if self.layout.is_shown(&layout::Pane::Log) {
                self.log.refresh(&mut self.debugger);
            }
            self.layout.fit_timeline(timeline::height(ui.style()));
            let current_places = self.layout.current_places();
            // A maximised tab fills the window; one that is gone (closed) maximises nothing.
            let maximised =
                self.layout
                    .maximised
                    .and_then(|tile| match self.layout.tree.tiles.get(tile) {
                        Some(egui_tiles::Tile::Pane(pane)) => Some((tile, pane.clone())),
                        _ => None,
                    });
            if maximised.is_none() {
                self.layout.maximised = None;
            }
            let mut panes = layout::Panes {
                debugger: &self.debugger,
                code: &mut self.code,
                registers: &mut self.registers,
                plot: &mut self.plot,
                timeline: &mut self.timeline,
                breakpoints: &mut self.breakpoints,
                watches: &mut self.watches,
                log: &mut self.log,
                lesson: self.lesson.as_mut(),
                help: &mut self.help,
                dialect_panels: &mut self.panels,
                out: &mut commands,
                places: &mut self.layout.places,
                current_places: &current_places,
            };
            match maximised {
                Some((tile, mut pane)) => {
                    use egui_tiles::Behavior as _;
                    ui.horizontal(|ui| {
                        let tab = ui
                            .selectable_label(true, pane.title())
                            .on_hover_text("Double-click: back to the layout");
                        let restore = ui.button("Restore layout");
                        if tab.double_clicked() || restore.clicked() {
                            panes.out.push(Command::ToggleMaximise(tile));
                        }
                    });
                    // Below the header row; a pane never asks to be dragged here (there is no
                    // tree to drop it in).
                    let rest = ui.available_rect_before_wrap();
                    let mut below = ui.new_child(egui::UiBuilder::new().max_rect(rest));
                    let _ = panes.pane_ui(&mut below, tile, &mut pane);
                }
                None => self.layout.tree.ui(&mut panes, ui),
            }
        });
        self.files.windows(&ctx, &self.prefs, &mut commands);
        settings::window(&ctx, &self.debugger, &mut self.settings, &mut commands);
        include_folders::window(
            &ctx,
            &self.prefs.include_folders,
            &mut self.include_folders,
            &mut commands,
        );
        if self.pending.is_some() {
            unsaved_prompt(&ctx, self.pending.as_ref(), &mut commands);
        }
        if let Some((path, reason)) = &self.confirm_replace
            && let Some(answer) = replace_prompt(&ctx, path, reason)
        {
            if answer {
                commands.push(Command::SaveSessionOver(path.clone()));
            } else {
                self.confirm_replace = None;
            }
        }

        if self.loading.is_some() {
            // The session being opened replaces this one: nothing more happens to it meanwhile.
            commands.clear();
            keyed.clear();
        }
        if !keyed.is_empty() {
            // The frame drew the state before the keys: the next one shows what they did.
            ctx.request_repaint();
        }
        for c in commands.into_iter().chain(keyed) {
            self.apply(&ctx, c);
        }
        self.prefs
            .register_formats
            .clone_from(&self.registers.every);
        self.prefs.only_used_registers = self.registers.only_used;

        let title = self.window_title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        let paced = self.debugger.is_running()
            && self.debugger.speed() == servoscope_core::debugger::Speed::Unlimited;
        if (self.debugger.is_running() && !paced) || self.files.is_waiting() {
            ctx.request_repaint();
        }
    }
}

/// A menu button whose popup holds fields (a text field, a combo box): it stays open while the
/// user clicks inside it, and closes on a click outside, Escape or its button (a plain menu
/// closes on any click, so its fields could not be used).
pub fn form_menu_button<R>(
    ui: &mut egui::Ui,
    title: &str,
    content: impl FnOnce(&mut egui::Ui) -> R,
) -> egui::Response {
    egui::containers::menu::MenuButton::new(title)
        .config(
            egui::containers::menu::MenuConfig::new()
                .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside),
        )
        .ui(ui, content)
        .0
}

/// A small dialog in the middle of the window.
pub fn dialog(title: &str) -> egui::Window<'static> {
    egui::Window::new(title)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
}

/// "Replace a file that is not a session?": true to replace, false to cancel, None meanwhile.
pub(super) fn replace_prompt(ctx: &egui::Context, path: &Path, reason: &str) -> Option<bool> {
    let mut answer = None;
    dialog("Replace file?").show(ctx, |ui| {
        ui.label(format!(
            "{} exists and is not a servoscope session ({reason}). Saving replaces it.",
            path.display()
        ));
        ui.horizontal(|ui| {
            if ui.button("Replace it").clicked() {
                answer = Some(true);
            }
            if ui.button("Keep it").clicked() {
                answer = Some(false);
            }
        });
    });
    answer
}

/// "Unsaved changes": save the session first, discard the changes, or cancel.
pub(super) fn unsaved_prompt(
    ctx: &egui::Context,
    pending: Option<&Pending>,
    out: &mut Vec<Command>,
) {
    let what = match pending {
        Some(Pending::Open(path)) => format!("opening {}", path.display()),
        Some(Pending::Example(_) | Pending::ExampleProject(_)) => "opening the example".to_string(),
        Some(Pending::Lesson(_)) => "opening the lesson".to_string(),
        Some(Pending::New(_)) => "starting a new program".to_string(),
        Some(Pending::Quit) | None => "closing servoscope".to_string(),
    };
    dialog("Unsaved changes").show(ctx, |ui| {
        ui.label(format!(
            "This debugging session has changes that are not saved. They are lost by {what}."
        ));
        ui.horizontal(|ui| {
            if ui.button("Save session").clicked() {
                out.push(Command::SaveSession);
            }
            if ui.button("Discard changes").clicked() {
                out.push(Command::DiscardAndContinue);
            }
            if ui.button("Cancel").clicked() {
                out.push(Command::CancelPending);
            }
        });
    });
}

impl ServoscopeApp {
    /// A frame of the window: [`ServoscopeApp::show`], then the run in progress goes to the
    /// worker thread until the next frame, asked for so that frames come a frame's time apart
    /// ([`FramePacer`]).
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let started = Instant::now();
        self.show(ui);
        self.record_frame_stats(ui.ctx(), started);
        self.debugger.hand_off();
        if self.debugger.is_running()
            && self.debugger.speed() == servoscope_core::debugger::Speed::Unlimited
        {
            let wait = self.pacer.wait(started, Instant::now());
            ui.ctx().request_repaint_after(wait);
        }
    }

    pub(super) fn record_frame_stats(&mut self, ctx: &egui::Context, started: Instant) {
        if let Some(stats) = &mut self.frame_stats {
            let m = self.debugger.machine();
            if let Some(report) = stats.record(started, Instant::now(), m.ticks(), m.tick_micros())
            {
                eprintln!("{report}");
                // A measurement run is not work to keep: close without "unsaved changes".
                self.allow_close = true;
                self.pending = None;
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                self.frame_stats = None;
            } else if !self.debugger.is_running() {
                // A program that ended still counts its frames to the last.
                ctx.request_repaint();
            }
        }
    }
}

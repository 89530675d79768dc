//! The dockable layout and the plots, through egui_kittest at the window sizes users have:
//! panels never overlap and keep their minimum sizes, close and reopen from the View menu,
//! reset, persist with the preferences; plots line up and fit their data.

use egui::{Key, Rect};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use servoscope::ui::layout::{Layout, Pane};
use servoscope::ui::{Command, Prefs, ServoscopeApp};
use servoscope_core::debugger::Speed;
use servoscope_core::machine::{Format, RunState};

fn harness_sized(app: ServoscopeApp, w: f32, h: f32) -> Harness<'static, ServoscopeApp> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(w, h))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    // The timeline settles to its height once the layout has been drawn once.
    h.run_steps(4);
    h
}

/// The area a pane's content gets: its tile less the tab bar.
fn content(rect: Rect) -> Rect {
    rect.with_min_y(rect.top() + 24.0)
}

fn assert_sound_layout(app: &ServoscopeApp, size: (f32, f32)) {
    let rects = app.layout.pane_rects();
    let window = Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(size.0, size.1));
    for (i, (pane, rect)) in rects.iter().enumerate() {
        assert!(
            window.contains_rect(*rect),
            "{size:?}: {pane:?} at {rect:?} leaves the window"
        );
        let room = content(*rect).size();
        let min = pane.min_size();
        assert!(
            room.x >= min.x && room.y >= min.y,
            "{size:?}: {pane:?} has {room:?}, needs {min:?}"
        );
        for (other, other_rect) in &rects[i + 1..] {
            let overlap = rect.intersect(*other_rect);
            assert!(
                overlap.width() <= 0.0 || overlap.height() <= 0.0,
                "{size:?}: {pane:?} {rect:?} overlaps {other:?} {other_rect:?}"
            );
        }
    }
}

#[test]
fn no_two_panels_overlap_and_each_keeps_its_minimum_size() {
    for (w, ht) in [(900.0, 600.0), (1280.0, 800.0), (2560.0, 1440.0)] {
        let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), w, ht);
        // Before the example makes its queue, the queue panel gives its room away.
        assert_eq!(h.state().layout.pane_rects().len(), 5);
        assert_sound_layout(h.state(), (w, ht));
        h.key_press(Key::F10);
        h.run_steps(3);
        assert_eq!(
            h.state().layout.pane_rects().len(),
            6,
            "program, registers, bits, plot, timeline, queues"
        );
        assert_sound_layout(h.state(), (w, ht));
    }
}

#[test]
fn a_larger_window_gives_the_plot_and_queues_their_share() {
    let sized = |w, h| {
        let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), w, h);
        h.key_press(Key::F10);
        h.run_steps(3);
        h
    };
    let small = sized(1280.0, 800.0);
    let large = sized(2560.0, 1440.0);
    let rect = |h: &Harness<'_, ServoscopeApp>, pane: &Pane| {
        h.state().layout.pane_rect(pane).expect("pane shown")
    };
    let queues = Pane::Dialect("Queues".into());
    for pane in [&Pane::Plot, &queues, &Pane::Program] {
        let (a, b) = (rect(&small, pane), rect(&large, pane));
        assert!(
            b.height() > a.height() * 1.5,
            "{pane:?} grows with the window: {} → {}",
            a.height(),
            b.height()
        );
    }
    // The timeline's two rows need no more room in a taller window.
    let (a, b) = (rect(&small, &Pane::Timeline), rect(&large, &Pane::Timeline));
    assert!((a.height() - b.height()).abs() < 2.0, "{a:?} vs {b:?}");
}

#[test]
fn panels_close_and_reopen_from_the_view_menu_and_reset() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 1280.0, 800.0);
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Plot panel").click();
    h.run_steps(3);
    assert!(!h.state().layout.contains(&Pane::Plot), "closed");
    assert!(
        h.state()
            .layout
            .pane_rects()
            .iter()
            .all(|(p, _)| *p != Pane::Plot)
    );
    // The others take its room and still do not overlap.
    assert_sound_layout(h.state(), (1280.0, 800.0));

    // The View menu stays open after a checkbox: reopen it there.
    if h.query_by_label("Plot panel").is_none() {
        h.get_by_label("View").click();
        h.run_steps(2);
    }
    h.get_by_label("Plot panel").click();
    h.run_steps(3);
    assert!(h.state().layout.contains(&Pane::Plot), "reopened");
    assert!(
        h.state()
            .layout
            .pane_rects()
            .iter()
            .any(|(p, r)| *p == Pane::Plot && r.width() > 100.0)
    );

    // Closing with the × on its tab works too.
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Bits, false),
    );
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Timeline, false),
    );
    h.run_steps(2);
    assert!(!h.state().layout.contains(&Pane::Bits));
    h.state_mut()
        .apply(&egui::Context::default(), Command::ResetLayout);
    h.run_steps(4);
    for pane in Pane::COMMON {
        assert!(
            h.state().layout.contains(&pane),
            "{pane:?} back after reset"
        );
    }
    assert_sound_layout(h.state(), (1280.0, 800.0));
}

#[test]
fn the_tab_close_button_closes_a_panel() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 1280.0, 800.0);
    let before = h.state().layout.pane_rects().len();
    // Each tab has a close button named "Close"; the first tab is the program's.
    let program_tab = h.get_by_label("Program").rect();
    let close = h
        .get_all_by_label("Close")
        .find(|n| program_tab.contains(n.rect().center()))
        .expect("the program tab has a close button");
    close.click();
    h.run_steps(3);
    assert!(!h.state().layout.contains(&Pane::Program));
    assert_eq!(h.state().layout.pane_rects().len(), before - 1);
}

#[test]
fn the_layout_is_kept_with_the_preferences() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 1280.0, 800.0);
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Bits, false),
    );
    h.run_steps(2);
    let mut prefs = h.state().prefs.clone();
    prefs.layout = Some(h.state().layout.clone());
    // As eframe stores it: text, read back on the next launch.
    let stored = ron::to_string(&prefs).expect("prefs serialise");
    let restored: Prefs = ron::from_str(&stored).expect("prefs read back");
    let h2 = harness_sized(ServoscopeApp::new(restored), 1280.0, 800.0);
    assert!(!h2.state().layout.contains(&Pane::Bits), "still closed");
    assert!(h2.state().layout.contains(&Pane::Plot));

    // Preferences from before layouts existed, or with a damaged layout, get the default.
    let old: Prefs = ron::from_str("(dark: false)").expect("old prefs");
    assert!(old.layout.is_none());
    let h3 = harness_sized(ServoscopeApp::new(old), 900.0, 600.0);
    assert_sound_layout(h3.state(), (900.0, 600.0));
    // A damaged layout costs the layout only, never the other preferences.
    let damaged = stored.replace("Registers", "Nonsense");
    assert_ne!(damaged, stored);
    let prefs: Prefs = ron::from_str(&damaged).expect("the preferences still read");
    assert!(prefs.layout.is_none());
    assert_eq!(prefs.speeds, h.state().prefs.speeds);
    let h4 = harness_sized(ServoscopeApp::new(prefs), 900.0, 600.0);
    assert_sound_layout(h4.state(), (900.0, 600.0));
}

#[test]
fn the_dialect_panels_follow_the_dialect() {
    let mut layout = Layout::standard(&["Queues"]);
    assert!(layout.contains(&Pane::Dialect("Queues".into())));
    layout.sync_dialect_panels(&["Stack", "Product"]);
    assert!(!layout.contains(&Pane::Dialect("Queues".into())));
    assert!(layout.contains(&Pane::Dialect("Stack".into())));
    assert!(layout.contains(&Pane::Dialect("Product".into())));
    layout.sync_dialect_panels(&[]);
    assert!(!layout.contains(&Pane::Dialect("Stack".into())));
    for pane in Pane::COMMON {
        assert!(layout.contains(&pane));
    }
}

#[test]
fn choosing_binary_does_not_widen_the_register_panel() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 900.0, 600.0);
    let width = |h: &Harness<'_, ServoscopeApp>| {
        h.state()
            .layout
            .pane_rects()
            .into_iter()
            .find(|(p, _)| *p == Pane::Registers)
            .map(|(_, r)| r.width())
            .expect("registers shown")
    };
    let before = width(&h);
    h.state_mut().registers.set_column(Some(Format::Binary));
    h.run_steps(3);
    assert_eq!(width(&h), before);
    assert_sound_layout(h.state(), (900.0, 600.0));
}

#[test]
fn go_to_tick_stays_in_view_with_seven_digit_ticks() {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("long.qsl", "loop: CLC INC, 13\nJMP loop");
    let mut h = harness_sized(app, 1280.0, 800.0);
    h.state_mut().debugger.goto_tick(1_234_567);
    for _ in 0..200 {
        if h.state().debugger.machine().ticks() == 1_234_567 {
            break;
        }
        h.step();
    }
    assert_eq!(h.state().debugger.machine().ticks(), 1_234_567);
    let timeline = h
        .state()
        .layout
        .pane_rect(&Pane::Timeline)
        .expect("timeline shown");
    let field = h.get_by_label("Go to tick").rect();
    assert!(
        timeline.contains_rect(field),
        "{field:?} inside {timeline:?}"
    );
    let slider = h.get_by_label("Timeline position").rect();
    assert!(timeline.contains_rect(slider));
    assert!(slider.width() > timeline.width() * 0.8, "the whole width");
}

/// Runs a move to its end and returns the harness.
fn moved(size: (f32, f32)) -> Harness<'static, ServoscopeApp> {
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("move.qsl", "MAV 2000, 386500, 80530640\nDLY 300\nEND");
    let mut h = harness_sized(app, size.0, size.1);
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(6);
    assert_eq!(h.state().debugger.machine().run_state(), RunState::Ended);
    h
}

#[test]
fn stacked_plots_share_their_left_and_right_edges() {
    for size in [(900.0, 600.0), (1280.0, 800.0), (2560.0, 1440.0)] {
        let h = moved(size);
        let frames = &h.state().plot.frames;
        assert_eq!(frames.len(), 2, "position and error plots");
        let (a, b) = (frames[0].rect, frames[1].rect);
        assert!(
            (a.left() - b.left()).abs() < 0.5 && (a.right() - b.right()).abs() < 0.5,
            "{size:?}: {a:?} vs {b:?}"
        );
        assert!(a.bottom() <= b.top(), "stacked, not overlapping");
        assert_eq!(frames[0].x, frames[1].x, "one time range");
    }
}

#[test]
fn a_constant_trace_gets_a_small_range_and_a_moving_one_fits_its_data() {
    let h = moved((1280.0, 800.0));
    let (lo, hi) = h.state().plot.frames[0].y;
    // Position went 0 → 2000: the range holds it with a little margin, no more.
    assert!(lo <= 0.0 && lo > -200.0, "{lo}");
    assert!((2000.0..2200.0).contains(&hi), "{hi}");

    // A program that never moves: the error is 0 all along.
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("still.qsl", "DLY 500\nEND");
    let mut h = harness_sized(app, 1280.0, 800.0);
    h.state_mut().debugger.set_speed(Speed::Unlimited);
    h.key_press(Key::F5);
    h.run_steps(6);
    assert!(!h.state().plot.frames.is_empty());
    for frame in &h.state().plot.frames {
        assert_eq!(frame.y, (-1.0, 1.0), "constant 0 shows as -1..1");
    }
}

fn wheel(h: &mut Harness<'_, ServoscopeApp>, at: egui::Pos2, dy: f32, modifiers: egui::Modifiers) {
    h.event(egui::Event::PointerMoved(at));
    h.step();
    h.event_modifiers(
        egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, dy),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Wheel,
            modifiers,
        },
        modifiers,
    );
    h.run_steps(6);
}

#[test]
fn the_wheel_zooms_and_pans_time_only() {
    let mut h = moved((1280.0, 800.0));
    let before = h.state().plot.frames[0];
    let span = |f: &servoscope::ui::plot::PlotFrame| f.x.1 - f.x.0;
    // Ctrl+wheel zooms in time.
    wheel(&mut h, before.rect.center(), 120.0, egui::Modifiers::CTRL);
    let zoomed = h.state().plot.frames[0];
    assert!(
        !h.state().plot.following,
        "zoomed: the view stops following"
    );
    assert!(
        span(&zoomed) < span(&before) * 0.95,
        "{before:?} → {zoomed:?}"
    );
    // y still fits the data: never panned or zoomed off it.
    assert!(zoomed.y.0 >= -200.0 && zoomed.y.1 <= 2200.0, "{zoomed:?}");
    assert!(zoomed.y.0 < zoomed.y.1);
    // The plain wheel moves along time, keeping the span.
    wheel(&mut h, before.rect.center(), 120.0, egui::Modifiers::NONE);
    let panned = h.state().plot.frames[0];
    assert!((span(&panned) - span(&zoomed)).abs() < span(&zoomed) * 0.01);
    assert!(panned.y.0 < panned.y.1);
    assert!(panned.x != zoomed.x, "moved along time");
    // "Reset view" shows everything again.
    h.get_by_label("Reset view").click();
    h.run_steps(3);
    assert!(h.state().plot.following);
    assert!((span(&h.state().plot.frames[0]) - span(&before)).abs() < 1.0);
}

/// Issue #9 item 9: at the default window size the queue's header words show with the ring,
/// not below the panel's edge.
#[test]
fn the_queue_header_decode_is_in_view_at_the_default_size() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 1280.0, 800.0);
    for _ in 0..3 {
        h.key_press(Key::F10);
        h.run_steps(2);
    }
    let queues = h
        .state()
        .layout
        .pane_rect(&Pane::Dialect("Queues".into()))
        .expect("queues shown");
    for label in ["size = 4", "len = 2", "head = 2", "tail = 0"] {
        let rect = h.get_by_label(label).rect();
        assert!(
            queues.contains_rect(rect),
            "{label} at {rect:?}, panel {queues:?}"
        );
    }
}

/// Every dialect's panels fit the smallest window beside the common ones.
#[test]
fn every_dialect_fits_the_smallest_window() {
    for dialect in servoscope_core::registry::DIALECTS {
        let (name, text) = dialect.examples[0];
        let mut app = ServoscopeApp::new(Prefs::default());
        app.load_program_as(dialect, name, text);
        let mut h = harness_sized(app, 900.0, 600.0);
        for _ in 0..3 {
            h.key_press(Key::F10);
            h.run_steps(2);
        }
        assert_sound_layout(h.state(), (900.0, 600.0));
    }
}

#[test]
fn panels_added_since_a_layout_was_saved_join_it_once() {
    // A layout saved by a build before the Breakpoints, Watches and Log panels: its preferences
    // have no list of known panels.
    let mut old = Layout::standard(&["Queues"]);
    for pane in [Pane::Breakpoints, Pane::Watches, Pane::Log] {
        old.set_shown(&pane, false);
    }
    let mut prefs = Prefs {
        layout: Some(old),
        ..Prefs::default()
    };
    let text = ron::to_string(&prefs).expect("prefs serialise");
    let without_list = text
        .split(",known_panes:")
        .next()
        .expect("the fields before the list")
        .to_string()
        + ")";
    let restored: Prefs = ron::from_str(&without_list).expect("older prefs read");
    let h = harness_sized(ServoscopeApp::new(restored), 1280.0, 800.0);
    for pane in [Pane::Breakpoints, Pane::Watches, Pane::Log] {
        assert!(
            h.state().layout.contains(&pane),
            "{pane:?} joins the old layout"
        );
    }
    assert_sound_layout(h.state(), (1280.0, 800.0));
    // A panel the user closed under this build stays closed.
    let mut closed = Layout::standard(&["Queues"]);
    closed.set_shown(&Pane::Watches, false);
    prefs.layout = Some(closed);
    prefs.known_panes = Pane::common_titles();
    let h = harness_sized(ServoscopeApp::new(prefs), 1280.0, 800.0);
    assert!(!h.state().layout.contains(&Pane::Watches));
}

/// Issue #22 item 18: at 900×600 the register table's columns all lie inside its panel (Hex
/// was cut off, with no scroll bar); with room, Binary joins them.
#[test]
fn the_register_columns_fit_their_panel_at_any_size() {
    for (size, binary) in [((900.0, 600.0), false), ((1920.0, 1080.0), true)] {
        let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), size.0, size.1);
        h.run_steps(2);
        let panel = h
            .state()
            .layout
            .pane_rect(&Pane::Registers)
            .expect("registers shown");
        for title in ["Location", "Name", "Value", "Hex"] {
            let rect = h.get_by_label(title).rect();
            assert!(
                panel.contains_rect(rect),
                "{title} at {rect:?}, panel {panel:?} in {size:?}"
            );
        }
        // The widest value of the Hex column (R0 = 0x0000_0000) ends inside the panel.
        let hex = h
            .get_all_by_label("0x0000_0000")
            .next()
            .expect("a hex value")
            .rect();
        assert!(
            hex.right() <= panel.right(),
            "hex at {hex:?}, panel {panel:?} in {size:?}"
        );
        assert_eq!(h.query_by_label("Binary").is_some(), binary, "{size:?}");
    }
}

/// Issue #22 item 16: a panel closed (its tab's ×, or View) and reopened from View comes back
/// where it was: a tab among its tabs, a split in its column; not a new narrow column.
#[test]
fn a_reopened_panel_comes_back_where_it_was() {
    let mut h = harness_sized(ServoscopeApp::new(Prefs::default()), 1280.0, 800.0);
    let rect_of = |h: &Harness<'_, ServoscopeApp>, pane: &Pane| h.state().layout.pane_rect(pane);
    // A tab: Watches, closed by its ×, reopened from View, is a tab beside Bits again.
    h.get_by_label("Watches").click();
    h.run_steps(2);
    let watches_tab = h.get_by_label("Watches").rect();
    let close = h
        .get_all_by_label("Close")
        .find(|n| watches_tab.contains(n.rect().center()))
        .expect("the Watches tab has a close button");
    close.click();
    h.run_steps(3);
    assert!(!h.state().layout.contains(&Pane::Watches));
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Watches, true),
    );
    h.run_steps(3);
    let tiles = &h.state().layout.tree.tiles;
    let parent = |pane: &Pane| tiles.find_pane(pane).and_then(|t| tiles.parent_of(t));
    assert!(parent(&Pane::Watches).is_some());
    assert_eq!(
        parent(&Pane::Watches),
        parent(&Pane::Bits),
        "a tab beside Bits again"
    );
    // A split: the plot, closed from View and reopened, is back in the left column below the
    // timeline, as wide as before (not a new column at the window's edge).
    let plot_before = rect_of(&h, &Pane::Plot).expect("plot shown");
    let timeline = rect_of(&h, &Pane::Timeline).expect("timeline shown");
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Plot, false),
    );
    h.run_steps(3);
    h.state_mut().apply(
        &egui::Context::default(),
        Command::ShowPane(Pane::Plot, true),
    );
    h.run_steps(4);
    let plot_after = rect_of(&h, &Pane::Plot).expect("plot back");
    assert!(
        (plot_after.left() - plot_before.left()).abs() < 2.0
            && (plot_after.right() - plot_before.right()).abs() < 2.0
            && plot_after.top() >= timeline.bottom(),
        "{plot_before:?} then {plot_after:?}"
    );
    assert_sound_layout(h.state(), (1280.0, 800.0));
}

/// #43 item 19: at 1366×768 a rung of four contacts shows its coil (the ladder shrinks to the
/// panel), and a double-clicked tab fills the window until it is double-clicked again.
#[test]
fn a_long_rung_fits_and_a_double_clicked_tab_fills_the_window() {
    let dl205 = servoscope_core::registry::by_name("dl205").expect("DL205");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(
        dl205,
        "four.dl205",
        "STR X0\nAND X1\nAND X2\nAND X3\nOUT Y0\nEND\n",
    );
    // Frames 50 ms apart, so two clicks (a frame per event) are a double-click.
    let mut h = Harness::builder()
        .with_size(egui::vec2(1366.0, 768.0))
        .with_step_dt(0.05)
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(4);
    let ladder = Pane::Dialect("Ladder".into());
    let pane = h
        .state()
        .layout
        .pane_rect(&ladder)
        .expect("the ladder shown");
    let coil = h.get_by_label("Ladder Y0 line 5").rect();
    assert!(
        pane.contains_rect(coil),
        "the coil {coil:?} inside the panel {pane:?}"
    );
    // Double-click the Registers tab: it alone fills the window.
    let tab = h.get_by_label("Registers").rect().center();
    h.event(egui::Event::PointerMoved(tab));
    h.step();
    for pressed in [true, false, true, false] {
        h.event(egui::Event::PointerButton {
            pos: tab,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.run_steps(3);
    assert!(h.state().layout.maximised.is_some(), "maximised");
    assert!(
        h.query_by_label("Ladder Y0 line 5").is_none(),
        "the others are hidden"
    );
    h.get_by_label("Restore layout").click();
    h.run_steps(3);
    assert!(h.state().layout.maximised.is_none());
    h.get_by_label("Ladder Y0 line 5");
}

/// #43 item 19: at 900×600 a lesson's steps get two thirds of their column (they showed three
/// lines).
#[test]
fn a_lesson_gets_room_in_a_small_window() {
    let path = std::env::temp_dir().join(format!("servoscope-{}-room.ron", std::process::id()));
    let lesson = servoscope_core::registry::lessons()
        .find(|(_, name, _)| *name == "fifo_lifo_task.ron")
        .map(|(_, _, text)| text)
        .expect("the FIFO/LIFO task");
    std::fs::write(&path, lesson).expect("written");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.open_path(path.clone());
    let h = harness_sized(app, 900.0, 600.0);
    let lesson = h.state().layout.pane_rect(&Pane::Lesson).expect("shown");
    assert!(lesson.height() >= 270.0, "{lesson:?}");
    let _ = std::fs::remove_file(path);
}

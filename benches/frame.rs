//! One frame of the window (no GPU: egui_kittest lays it out), for a small program and for a
//! 100,000-line one: the code view lays out only the visible rows, so both cost about the same.
//! And a 2,000-rung DL205 program with its Ladder and I/O board open: the ladder draws only the
//! rungs on screen.
//!
//! `cargo bench --bench frame`

use criterion::{Criterion, criterion_group, criterion_main};
use egui_kittest::Harness;
use servoscope::ui::{Prefs, ServoscopeApp};

fn harness(lines: usize) -> Harness<'static, ServoscopeApp> {
    let text: String = (1..=lines)
        .map(|i| format!("WRP 20, {i} ; line {i}\n"))
        .collect();
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program("bench.qsl", &text);
    app.debugger.goto_tick(lines as u64 / 2);
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(4);
    h
}

/// A DL205 program of `rungs` rungs (seal-ins, branches, a timer every 25th), opened in the
/// window with its Ladder beside the program, stopped in the middle of a scan and scrolled to
/// its middle rungs.
fn ladder_harness(rungs: usize) -> Harness<'static, ServoscopeApp> {
    let mut text = String::new();
    for i in 0..rungs {
        let c = |k: usize| format!("C{:o}", k % 2000);
        if i % 25 == 0 {
            text += &format!(
                "STR X{:o}\nTMR T{:o} K{}\n",
                i % 8,
                (i / 25) % 256,
                10 + i % 90
            );
        } else {
            text += &format!(
                "STR X{:o}\nOR {}\nSTR {}\nORN {}\nANDSTR\nANDN X{:o}\nOUT {}\n",
                i % 8,
                c(i),
                c(i + 7),
                c(i + 3),
                (i + 1) % 8,
                c(i)
            );
        }
    }
    text += "END\n";
    let dl205 = servoscope_core::registry::by_name("dl205").expect("registered");
    let mut app = ServoscopeApp::new(Prefs::default());
    app.load_program_as(dl205, "rungs.dl205", &text);
    app.debugger.goto_tick(3);
    let mut h = Harness::builder()
        .with_size(egui::vec2(1280.0, 800.0))
        .build_ui_state(|ui, app: &mut ServoscopeApp| app.show(ui), app);
    h.run_steps(4);
    // Into the middle of a scan: half the rungs are "not yet this scan".
    for _ in 0..(rungs * 3) {
        h.state_mut().debugger.step_command();
    }
    // Scroll the ladder to its middle.
    let ladder = h
        .state()
        .layout
        .pane_rect(&servoscope::ui::layout::Pane::Dialect("Ladder".into()));
    if let Some(rect) = ladder {
        h.event(egui::Event::PointerMoved(rect.center()));
        for _ in 0..50 {
            h.event(egui::Event::MouseWheel {
                unit: egui::MouseWheelUnit::Page,
                delta: egui::vec2(0.0, -10.0),
                modifiers: egui::Modifiers::NONE,
                phase: egui::TouchPhase::Move,
                source: egui::MouseWheelSource::Unknown,
            });
            h.step();
        }
    }
    h.run_steps(2);
    h
}

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("frame");
    group.sample_size(20);
    for lines in [20, 100_000] {
        let mut h = harness(lines);
        group.bench_function(format!("a frame with a {lines}-line program"), |b| {
            b.iter(|| h.step())
        });
    }
    let mut h = ladder_harness(2_000);
    assert!(
        h.state().debugger.pos().step > 0,
        "the bench stands inside a scan"
    );
    group.bench_function("a frame with a 2,000-rung ladder mid-scan", |b| {
        b.iter(|| h.step())
    });
    group.finish();
}

criterion_group!(frame_benches, benches);
criterion_main!(frame_benches);

//! One frame of the window (no GPU: egui_kittest lays it out), for a small program and for a
//! 100,000-line one: the code view lays out only the visible rows, so both cost about the same.
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

fn benches(c: &mut Criterion) {
    let mut group = c.benchmark_group("frame");
    group.sample_size(20);
    for lines in [20, 100_000] {
        let mut h = harness(lines);
        group.bench_function(format!("a frame with a {lines}-line program"), |b| {
            b.iter(|| h.step())
        });
    }
    group.finish();
}

criterion_group!(frame_benches, benches);
criterion_main!(frame_benches);

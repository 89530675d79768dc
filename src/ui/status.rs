//! What happened: the status bar (run state, tick, time, steps, the last command explained),
//! the fault banner, and notices such as a file that could not be opened.

use egui::RichText;

use super::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::{Pos, RunState};

/// The run state as the status bar words it.
pub fn state_text(debugger: &Debugger) -> String {
    let m = debugger.machine();
    if debugger.has_errors() {
        return "not assembled".to_string();
    }
    if let Some(reached) = debugger.back_searched_to() {
        let tick = debugger.dialect().vocabulary.tick;
        return format!("searching back (at {tick} {}; Pause cancels)", reached.tick);
    }
    match (debugger.is_running(), m.run_state()) {
        (true, RunState::Running) => "running".to_string(),
        (true, state) => format!("running ({})", state.label()),
        (false, RunState::Running) if m.pos() == Pos::default() => "ready".to_string(),
        (false, RunState::Running) => "paused".to_string(),
        (false, state) => state.label().to_string(),
    }
}

pub fn status_bar(ui: &mut egui::Ui, debugger: &Debugger) {
    let p = palette(ui.visuals().dark_mode);
    let m = debugger.machine();
    let words = debugger.dialect().vocabulary;
    let time = time_text(m.ticks().saturating_mul(u64::from(m.tick_micros())));
    ui.horizontal(|ui| {
        let state = state_text(debugger);
        let colour = match m.run_state() {
            RunState::Faulted => p.error,
            RunState::Ended => p.dim,
            _ if debugger.is_running() => p.bit_on,
            _ => p.text,
        };
        ui.label(RichText::new(state).color(colour).strong());
        ui.separator();
        let pos = m.pos();
        if pos.step == 0 {
            ui.monospace(format!("{} {}", words.tick, pos.tick));
        } else {
            // Inside a scan: how far into it.
            ui.monospace(format!(
                "{} {}, {} {}",
                words.tick, pos.tick, words.step, pos.step
            ))
            .on_hover_text(format!(
                "{} {} of {} {} have run",
                pos.step, words.steps, words.tick, pos.tick
            ));
        }
        ui.separator();
        ui.monospace(time);
        ui.separator();
        ui.monospace(format!("{} {}", words.steps, m.steps()));
        if let Some(rate) = debugger.run_rate() {
            ui.separator();
            ui.monospace(rate_text(rate, m.tick_micros(), words.ticks))
                .on_hover_text(format!("{} simulated per second of wall time", words.ticks));
        }
        if let Some(event) = debugger.event() {
            ui.separator();
            ui.label(
                RichText::new(event.describe_with(words.tick, &|l| debugger.where_line(l)))
                    .color(p.dim),
            );
        }
    });
    ui.horizontal(|ui| {
        let line = m
            .last_line()
            .map_or(String::new(), |l| format!("{}: ", debugger.where_line(l)));
        let errors = debugger.error_count();
        let text = match m.explain_last() {
            // Step and Run are disabled: say why, not which key steps.
            _ if errors > 0 => format!(
                "The program does not assemble ({errors} error(s)): fix it (see Problems) to run."
            ),
            Some(e) => format!("{line}{e}"),
            None => "Press F10 to step, F5 to run.".to_string(),
        };
        ui.label(RichText::new(text).monospace().color(p.text));
    });
}

/// A run's speed: `152.3 M ticks/s (×18,276 real time)`.
pub fn rate_text(ticks_per_second: f64, tick_micros: u32, ticks: &str) -> String {
    let real_time = ticks_per_second * f64::from(tick_micros) / 1e6;
    let rate = if ticks_per_second >= 1e6 {
        format!("{:.1} M ", ticks_per_second / 1e6)
    } else if ticks_per_second >= 1e3 {
        format!("{:.1} k ", ticks_per_second / 1e3)
    } else if ticks_per_second >= 10.0 {
        format!("{ticks_per_second:.0} ")
    } else {
        // A slow run (10 instructions a second through a long scan) is not "0 scans/s".
        format!("{} ", two_significant(ticks_per_second))
    };
    let factor = if real_time >= 10.0 {
        servoscope_core::machine::value::group_thousands(real_time.round() as u64)
    } else if real_time >= 0.01 || real_time == 0.0 {
        format!("{real_time:.2}")
    } else {
        two_significant(real_time)
    };
    format!("{rate}{ticks}/s (×{factor} real time)")
}

/// A small positive number to two significant digits: 0.55, 0.0055.
fn two_significant(v: f64) -> String {
    if v <= 0.0 || !v.is_finite() {
        return "0".into();
    }
    let decimals = (1.0 - v.log10().floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

pub fn fault_banner(ui: &mut egui::Ui, debugger: &Debugger) {
    let Some(fault) = debugger.machine().fault() else {
        return;
    };
    let p = palette(ui.visuals().dark_mode);
    egui::Frame::new()
        .fill(p.error.gamma_multiply(0.25))
        .stroke(egui::Stroke::new(1.0, p.error))
        .inner_margin(6.0)
        .corner_radius(4.0)
        .show(ui, |ui| {
            ui.set_width(ui.available_width());
            ui.label(
                RichText::new(format!(
                    "Fault: {} at {}",
                    fault.kind,
                    debugger.where_line(fault.line)
                ))
                .strong()
                .color(p.error),
            );
            ui.label(&fault.message);
            ui.label(
                RichText::new(
                    "Every location keeps its value: inspect them, then Reset (Ctrl+Shift+F5).",
                )
                .small()
                .color(p.dim),
            );
        });
}

/// A dismissible message. Returns true when dismissed.
pub fn notice_banner(ui: &mut egui::Ui, text: &str) -> bool {
    let p = palette(ui.visuals().dark_mode);
    let mut dismissed = false;
    egui::Frame::new()
        .fill(p.written.gamma_multiply(0.2))
        .inner_margin(6.0)
        .corner_radius(4.0)
        .show(ui, |ui| {
            // Dismiss first and the text wrapped beside it: a long notice (a file's path and
            // what was dropped from it) never pushes the button out of a narrow window.
            ui.horizontal(|ui| {
                dismissed = ui.button("Dismiss").clicked();
                ui.add(egui::Label::new(text).wrap());
            });
        });
    dismissed
}

/// Simulated time as people read it: `360.120 ms` under a minute, `2:21:12.000` beyond.
pub fn time_text(micros: u64) -> String {
    if micros < 60_000_000 {
        return format!("{:.3} ms", micros as f64 / 1000.0);
    }
    let ms = micros / 1000;
    let (h, m, s, rest) = (ms / 3_600_000, ms / 60_000 % 60, ms / 1000 % 60, ms % 1000);
    format!("{h}:{m:02}:{s:02}.{rest:03}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_beyond_a_minute_read_as_clock_time() {
        assert_eq!(time_text(360_120), "360.120 ms");
        assert_eq!(time_text(59_999_999), "59999.999 ms");
        assert_eq!(time_text(60_000_000), "0:01:00.000");
        // 70,600,000 ticks of 120 µs: the 8472000.000 ms.
        assert_eq!(time_text(70_600_000 * 120), "2:21:12.000");
    }

    #[test]
    fn a_rate_reads_in_millions_and_as_a_factor_of_real_time() {
        // 120 µs ticks: 250 M ticks/s simulate 30,000 s each second.
        assert_eq!(
            rate_text(250e6, 120, "ticks"),
            "250.0 M ticks/s (×30,000 real time)"
        );
        // 1 ms scans: 2,500 a second are 2.5 × real time.
        assert_eq!(
            rate_text(2500.0, 1000, "scans"),
            "2.5 k scans/s (×2.50 real time)"
        );
        assert_eq!(
            rate_text(40.0, 1000, "scans"),
            "40 scans/s (×0.04 real time)"
        );
        // 10 instructions a second through an 18-instruction scan of 10 ms: not "0 scans/s".
        assert_eq!(
            rate_text(10.0 / 18.0, 10_000, "scans"),
            "0.56 scans/s (×0.0056 real time)"
        );
    }
}

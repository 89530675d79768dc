//! DL205's own panels (built with the window only): the accumulator stack, and the current
//! rung's power flow.

use egui::{Color32, RichText};
use servoscope_core::debugger::Action;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::dl205::program::{Op, Test, bit_name};
use servoscope_core::machine::dl205::{Dl205, LEVELS, StackMove, bcd_value};

pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    // Timers and stages first: they show only for programs that have them, and then they are
    // what the program is about (their tabs stay in view in a narrow pane).
    crate::ui::dialects::plc::panels(vec![
        Box::new(StagesPanel),
        Box::new(StackPanel::default()),
        Box::new(RungPanel),
    ])
}

fn bcd_text(v: u32) -> String {
    match bcd_value(v, 8) {
        Some(n) => format!("{n}"),
        None => "not BCD".into(),
    }
}

#[derive(Default)]
pub struct StackPanel {
    pair: String,
}

impl DialectPanel for StackPanel {
    fn title(&self) -> &'static str {
        "Accumulator stack"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Dl205>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("dl205_stack")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.label(
                    RichText::new(if m.load_pending {
                        "load pending: the next load pushes ACC"
                    } else {
                        "no load pending: the next load replaces ACC"
                    })
                    .color(if m.load_pending { p.written } else { p.dim }),
                );
                egui::Grid::new("dl205_levels")
                    .num_columns(4)
                    .spacing([12.0, 2.0])
                    .show(ui, |ui| {
                        for h in ["", "hex", "BCD", ""] {
                            ui.strong(h);
                        }
                        ui.end_row();
                        let acc_note = match m.moved {
                            StackMove::Pop { .. }
                                if matches!(
                                    m.program
                                        .instrs
                                        .get(m.last.unwrap_or(0) as usize)
                                        .map(|i| i.op),
                                    Some(Op::Pop)
                                ) =>
                            {
                                "L1 rose into ACC"
                            }
                            _ if m.acc != m.before.0 => "changed",
                            _ => "",
                        };
                        ui.monospace(RichText::new("ACC").strong());
                        // As bright as the levels below it (the default text colour read
                        // as greyed out beside them).
                        let acc_colour = if acc_note.is_empty() {
                            p.text
                        } else {
                            p.written
                        };
                        ui.monospace(RichText::new(format!("{:08X}", m.acc)).color(acc_colour));
                        ui.monospace(RichText::new(bcd_text(m.acc)).color(acc_colour));
                        ui.label(RichText::new(acc_note).color(p.written));
                        ui.end_row();
                        for level in 0..LEVELS {
                            let v = m.stack[level];
                            let used = level < m.depth as usize;
                            let colour = if used {
                                p.text
                            } else {
                                p.dim.gamma_multiply(0.6)
                            };
                            let note = match (m.moved, level) {
                                (StackMove::Push { entered, .. }, 0) => {
                                    format!("{entered:08X} pushed in")
                                }
                                (
                                    StackMove::Push {
                                        lost: Some(lost), ..
                                    },
                                    7,
                                ) => format!("{lost:08X} fell off the bottom"),
                                (StackMove::Pop { value }, 0) => {
                                    format!("{value:08X} popped; levels rose")
                                }
                                (StackMove::Overwrite { value }, 0) => {
                                    format!("overwritten: {value:08X}")
                                }
                                _ => String::new(),
                            };
                            ui.monospace(RichText::new(format!("L{}", level + 1)).color(colour));
                            ui.monospace(RichText::new(format!("{v:08X}")).color(colour));
                            ui.monospace(RichText::new(bcd_text(v)).color(colour));
                            ui.label(RichText::new(note).size(12.0).color(p.written));
                            ui.end_row();
                        }
                    });
                ui.label(
                    RichText::new(format!("depth {} of {LEVELS}", m.depth))
                        .size(12.0)
                        .color(p.dim),
                );
                ui.separator();
                ui.horizontal(|ui| {
                    let label = ui.label("V pair");
                    ui.add(egui::TextEdit::singleline(&mut self.pair).desired_width(70.0))
                        .labelled_by(label.id);
                    if let Some(loc) = servoscope_core::machine::dl205::view::parse_name(&self.pair)
                        && loc.space == servoscope_core::machine::dl205::view::V
                        && (loc.index as usize) + 1 < servoscope_core::machine::dl205::V_WORDS
                    {
                        let v = m.pair(loc.index);
                        ui.monospace(format!("{v:08X} = BCD {} = {v}", bcd_text(v)));
                    }
                });
                for (flag, line, name) in [
                    (
                        servoscope_core::machine::dl205::program::sp::SP53,
                        m.sp53_line,
                        "SP53 divide by zero",
                    ),
                    (
                        servoscope_core::machine::dl205::program::sp::SP75,
                        m.sp75_line,
                        "SP75 non-BCD data",
                    ),
                ] {
                    if m.sp[flag] {
                        ui.label(
                            RichText::new(format!(
                                "{name}, set on line {}",
                                line.map_or("?".into(), |l| l.to_string())
                            ))
                            .color(p.error),
                        );
                    }
                }
            });
    }
}

pub struct RungPanel;

impl DialectPanel for RungPanel {
    fn title(&self) -> &'static str {
        "Rung power"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Dl205>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        let instrs = &m.program.instrs;
        // The rung around the current (or last) instruction.
        let at = m.last.map_or(0, |l| l as usize);
        let starts = servoscope_core::machine::dl205::program::rung_starts(instrs);
        let start = starts
            .iter()
            .rev()
            .find(|&&s| s <= at)
            .copied()
            .unwrap_or(0);
        let end = starts
            .iter()
            .find(|&&s| s > at)
            .copied()
            .unwrap_or(instrs.len());
        egui::ScrollArea::both()
            .id_salt("dl205_rung")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.label(
                    RichText::new(format!("scan {}, instruction {}", m.tick, m.step)).color(p.dim),
                );
                for (i, ins) in instrs.iter().enumerate().take(end).skip(start) {
                    let power = m.power.get(i).copied().flatten();
                    let (dot, colour) = match power {
                        Some(true) => ("[1]", Color32::from_rgb(60, 170, 90)),
                        Some(false) => ("[0]", p.dim),
                        None => ("[ ]", p.dim),
                    };
                    let contact = match ins.op {
                        Op::Str(Test::Bit(b, neg))
                        | Op::And(Test::Bit(b, neg))
                        | Op::Or(Test::Bit(b, neg)) => {
                            format!(
                                "  {} is {}",
                                bit_name(b),
                                if m.bit(b) != neg { "closed" } else { "open" }
                            )
                        }
                        _ => String::new(),
                    };
                    let skipped = ins.op.is_output()
                        && !matches!(ins.op, Op::Coil(_))
                        && power == Some(false);
                    let mut text =
                        RichText::new(format!("{dot} {}{contact}", ins.text)).monospace();
                    text = if skipped {
                        text.color(p.dim).italics()
                    } else {
                        text.color(colour)
                    };
                    let row = ui.label(text);
                    if skipped {
                        row.on_hover_text("Not powered: skipped this scan");
                    }
                }
                ui.separator();
                let stack: Vec<&str> = m
                    .bstack
                    .iter()
                    .map(|b| if *b { "1" } else { "0" })
                    .collect();
                ui.monospace(format!(
                    "boolean stack: {}",
                    if stack.is_empty() {
                        "empty".into()
                    } else {
                        stack.join(" ")
                    }
                ));
            });
    }
}

/// Every SG/ISG in program order: active, clean-up pending or off, and which instruction last
/// changed it and when (click to go there).
pub struct StagesPanel;

impl DialectPanel for StagesPanel {
    fn title(&self) -> &'static str {
        "Stages"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger.machine_as::<Dl205>().is_some_and(|m| {
            m.program
                .instrs
                .iter()
                .any(|i| matches!(i.op, Op::Sg { .. }))
        })
    }
    fn wants_focus(&self, debugger: &Debugger) -> bool {
        self.has_content(debugger)
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Dl205>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        let ticks = debugger.dialect().vocabulary.tick;
        egui::ScrollArea::both()
            .id_salt("dl205_stages")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                egui::Grid::new("dl205_stages_grid")
                    .num_columns(3)
                    .spacing([10.0, 4.0])
                    .striped(true)
                    .show(ui, |ui| {
                        for ins in &m.program.instrs {
                            let Op::Sg { stage, initial, .. } = ins.op else {
                                continue;
                            };
                            let name = format!("S{stage:o}");
                            let on = m.s.get(stage as usize).copied().unwrap_or(false);
                            let pending = !on
                                && m.stage_marks.get(stage as usize).copied().unwrap_or(false);
                            let title = format!("{} {name}", if initial { "ISG" } else { "SG" });
                            if ui
                                .add(
                                    egui::Button::new(RichText::new(&title).monospace())
                                        .frame(false),
                                )
                                .on_hover_text(format!("Line {}: click to show it", ins.line))
                                .clicked()
                            {
                                out.push(Command::ShowLine(ins.line));
                            }
                            let (state, colour) = if on {
                                ("active", p.bit_on)
                            } else if pending {
                                ("clean-up pending", p.written)
                            } else {
                                ("off", p.dim)
                            };
                            ui.label(RichText::new(state).color(colour))
                                .on_hover_text(match state {
                                    "active" => "The stage runs every scan",
                                    "off" => "The stage is skipped",
                                    _ => "Turned off: the next scan runs it once with no power, so its outputs go off and its timers reset",
                                })
                                .widget_info(|| {
                                    egui::WidgetInfo::labeled(
                                        egui::Role::Label,
                                        true,
                                        format!("{name} {state}"),
                                    )
                                });
                            match m.stage_changes.iter().find(|c| c.stage == stage) {
                                Some(change) => {
                                    let text = format!(
                                        "changed by line {} at {ticks} {}",
                                        change.line, change.at.tick
                                    );
                                    if ui
                                        .link(&text)
                                        .on_hover_text("Go back to just after that instruction")
                                        .clicked()
                                    {
                                        out.push(Command::Debug(Action::GoTo(change.at)));
                                    }
                                }
                                None => {
                                    ui.label(
                                        RichText::new(if initial {
                                            "on from the start (ISG)"
                                        } else {
                                            "not changed yet"
                                        })
                                        .color(p.dim),
                                    );
                                }
                            }
                            ui.end_row();
                        }
                    });
            });
    }
}

//! OpenNet's own panels (built with the window only): the data registers read by type, the bit
//! areas in groups of eight, and the logic state with the error lamp.

use egui::{Color32, RichText, vec2};
use servoscope_core::debugger::Action;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::opennet::program::{Area, Op, Ty, point_name};
use servoscope_core::machine::opennet::view::{SPECIAL_SPACE, area_space};
use servoscope_core::machine::opennet::{M8003, M8004, OpenNet};
use servoscope_core::machine::{Loc, MachineView};

pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    crate::ui::dialects::plc::panels(vec![Box::new(DataPanel::default()), Box::new(LogicPanel)])
}

/// The type of the instruction about to run (or last run), which picks the reading.
/// The data type of the instruction about to run, or else of the one just run: with its line
/// and which of the two it is, so the panel says whose reading it shows.
fn current_type(m: &OpenNet) -> Option<(Ty, usize, &'static str)> {
    let at = |i: u32| m.program.instrs.get(i as usize);
    [(at(m.pc), "next to run"), (m.last.and_then(at), "just run")]
        .into_iter()
        .find_map(|(instr, when)| {
            let instr = instr?;
            match instr.op {
                Op::Mov { ty, .. }
                | Op::Arith { ty, .. }
                | Op::Step { ty, .. }
                | Op::WordCompare { ty, .. }
                | Op::WordLogic { ty, .. }
                | Op::Shift { ty, .. }
                | Op::Convert { ty, .. } => Some((ty, instr.line, when)),
                _ => None,
            }
        })
}

#[derive(Default)]
pub struct DataPanel {
    word_from: String,
}

impl DialectPanel for DataPanel {
    fn title(&self) -> &'static str {
        "Data by type"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<OpenNet>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        let at_hand = current_type(m);
        let ty = at_hand.map(|(t, _, _)| t);
        egui::ScrollArea::both()
            .id_salt("opennet_data")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.label(
                    RichText::new(match ty {
                        Some(t) => {
                            let (_, line, when) = at_hand.unwrap_or((t, 0, ""));
                            format!("Read as {} (line {line}, {when})", t.letter())
                        }
                        None => "Each register as W and I, each pair as D and L".into(),
                    })
                    .color(p.dim),
                );
                let highlight = |t: Ty| ty == Some(t);
                let cell = |ui: &mut egui::Ui, text: String, on: bool| {
                    let mut r = RichText::new(text).monospace();
                    if on {
                        r = r.strong().color(p.written);
                    }
                    ui.label(r);
                };
                egui::Grid::new("opennet_types")
                    .num_columns(5)
                    .spacing([10.0, 2.0])
                    .striped(true)
                    .show(ui, |ui| {
                        for h in ["", "W", "I", "D (pair)", "L (pair)"] {
                            ui.strong(h);
                        }
                        ui.end_row();
                        for &n in m.program.used_regs.iter().take(200) {
                            let w = m.d[n as usize];
                            ui.monospace(format!("D{n}"));
                            cell(ui, format!("{w}"), highlight(Ty::W));
                            cell(ui, format!("{}", w as i16), highlight(Ty::I));
                            if (n as usize) + 1 < m.d.len() {
                                let pair = (u32::from(w) << 16) | u32::from(m.d[n as usize + 1]);
                                cell(ui, format!("{pair}"), highlight(Ty::D));
                                cell(ui, format!("{}", pair as i32), highlight(Ty::L));
                            }
                            ui.end_row();
                        }
                    });
                ui.label(
                    RichText::new("A pair Dn·Dn+1 keeps its upper word in Dn.")
                        .size(12.0)
                        .color(p.dim),
                );
                ui.separator();
                // Bit areas in groups of eight, with a word reading from any point.
                for area in [Area::I, Area::Q, Area::M, Area::R] {
                    let groups: Vec<u32> = {
                        let mut g: Vec<u32> = m
                            .program
                            .used_bits
                            .iter()
                            .filter(|(a, _)| *a == area)
                            .map(|(_, i)| i / 8)
                            .collect();
                        g.dedup();
                        g
                    };
                    for group in groups.into_iter().take(16) {
                        ui.horizontal(|ui| {
                            ui.monospace(format!(
                                "{}–{}",
                                point_name(area, group * 8),
                                point_name(area, group * 8 + 7)
                            ));
                            for i in group * 8..group * 8 + 8 {
                                let on = m.read(Loc::new(area_space(area), i)) != 0;
                                let (fill, text) = if on {
                                    (p.bit_on, Color32::WHITE)
                                } else {
                                    (p.bit_off, p.dim)
                                };
                                ui.add(
                                    egui::Button::new(
                                        RichText::new(if on { "1" } else { "0" })
                                            .monospace()
                                            .color(text),
                                    )
                                    .fill(fill)
                                    .min_size(vec2(16.0, 16.0)),
                                )
                                .on_hover_text(point_name(area, i));
                            }
                        });
                    }
                }
                ui.horizontal(|ui| {
                    let label = ui.label("Word from");
                    ui.add(egui::TextEdit::singleline(&mut self.word_from).desired_width(60.0))
                        .labelled_by(label.id);
                    let area = servoscope_core::machine::opennet::view::parse_name(&self.word_from)
                        .and_then(|loc| {
                            let area = match loc.space {
                                servoscope_core::machine::opennet::view::I => Area::I,
                                servoscope_core::machine::opennet::view::Q => Area::Q,
                                servoscope_core::machine::opennet::view::M => Area::M,
                                servoscope_core::machine::opennet::view::R => Area::R,
                                _ => return None,
                            };
                            Some((area, loc))
                        });
                    if let Some((area, loc)) = area {
                        let word = servoscope_core::machine::opennet::program::Word::Bits {
                            area,
                            index: loc.index,
                            repeat: false,
                        };
                        let w = m.read_word(&word, 1, 0);
                        let dw = m.read_word(&word, 2, 0);
                        ui.monospace(format!(
                            "W {w}  I {}  D {dw}  L {}",
                            w as u16 as i16, dw as i32
                        ));
                    }
                });
            });
    }
}

pub struct LogicPanel;

impl DialectPanel for LogicPanel {
    fn title(&self) -> &'static str {
        "Logic and errors"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<OpenNet>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("opennet_logic")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                let error = m.special[M8004];
                ui.horizontal_wrapped(|ui| {
                    let (fill, text) = if error {
                        (p.error, "M8004 ERROR")
                    } else {
                        (p.bit_off, "M8004 no error")
                    };
                    ui.add(
                        egui::Button::new(RichText::new(text).strong().color(Color32::WHITE))
                            .fill(fill),
                    )
                    .on_hover_text("The execution-error relay (the controller's ERROR LED)");
                    if ui
                        .add_enabled(error, egui::Button::new("Clear errors"))
                        .on_hover_text("Set M8004 to 0 (the error count and record stay)")
                        .clicked()
                    {
                        out.push(Command::Debug(Action::SetValue(
                            Loc::new(SPECIAL_SPACE, M8004 as u32),
                            0,
                        )));
                    }
                    let mut stop = debugger.break_on_error();
                    if ui
                        .checkbox(&mut stop, "Break on error")
                        .on_hover_text("Stop a run when M8004 turns on")
                        .changed()
                    {
                        out.push(Command::Debug(Action::SetBreakOnError(stop)));
                    }
                });
                ui.label(format!("errors: {}", m.error_count));
                if let Some(e) = m.last_error {
                    ui.label(
                        RichText::new(format!(
                            "last: {} on line {} in scan {}",
                            e.kind, e.line, e.tick
                        ))
                        .color(p.error),
                    );
                }
                let carry = m.special[M8003];
                ui.label(
                    RichText::new(format!("M8003 carry/borrow = {}", u8::from(carry)))
                        .color(if carry { p.written } else { p.dim }),
                );
                ui.separator();
                ui.monospace(format!("RLO = {}", u8::from(m.rlo)));
                let stack = |s: &[bool]| {
                    if s.is_empty() {
                        "empty".to_string()
                    } else {
                        s.iter()
                            .map(|b| if *b { "1" } else { "0" })
                            .collect::<Vec<_>>()
                            .join(" ")
                    }
                };
                ui.monospace(format!("block stack:  {}", stack(&m.blocks)));
                ui.monospace(format!("branch stack: {}", stack(&m.branches)));
                ui.monospace(format!(
                    "MC = {}{}",
                    u8::from(m.mc),
                    if m.mc {
                        ""
                    } else {
                        " (in an MCS area that is off: outputs off)"
                    }
                ));
                if !m.edges.0.is_empty() {
                    ui.monospace(format!("SOTU/SOTD memories: {}", stack(&m.edges.0)));
                }
                if !m.pulses.0.is_empty() {
                    ui.monospace(format!(
                        "counter/SFR pulse memories: {}",
                        stack(&m.pulses.0)
                    ));
                }
                ui.monospace(format!("scan {}, instruction {}", m.tick, m.step));
            });
    }
}

//! TML's own panels (built with the window only): the product register bit by bit with its
//! PROD and PRODH windows and the last multiply, and the drive's program state (call stack,
//! event and WAIT!, error bits).

use egui::{Color32, RichText, Sense, Stroke, vec2};
use servoscope_core::debugger::Action;

use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;
use servoscope_core::debugger::Debugger;
use servoscope_core::machine::MachineView;
use servoscope_core::machine::tml::{Event, STACK_DEPTH, Tml, d, der, mer, srl};
use servoscope_core::machine::value::q16_exact;

pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    vec![
        Box::new(ProductPanel),
        Box::new(DrivePanel),
        Box::new(DriveDataPanel),
        Box::new(LabelsPanel),
    ]
}

/// A datum's value as its type reads: uint unsigned, int and long signed, fixed as its exact
/// decimal.
fn typed_value(raw: u32, ty: servoscope_core::machine::tml::Ty) -> String {
    match ty {
        servoscope_core::machine::tml::Ty::Uint => {
            format!("{} (0x{:04X})", raw & 0xFFFF, raw & 0xFFFF)
        }
        servoscope_core::machine::tml::Ty::Int => (raw as u16 as i16).to_string(),
        servoscope_core::machine::tml::Ty::Long => (raw as i32).to_string(),
        servoscope_core::machine::tml::Ty::Fixed => q16_exact(i64::from(raw as i32)),
    }
}

/// Tables A and B of spec §2 and the user variables, with type, address, value and access.
pub struct DriveDataPanel;

impl DialectPanel for DriveDataPanel {
    fn title(&self) -> &'static str {
        "Drive data"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Tml>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("drive_data_scroll")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                let upgrade = m.data[d::UPGRADE as usize];
                let mcr = m.mcr();
                ui.label(
                    RichText::new(format!(
                        "MCR 0x{mcr:04X}: {}{}{}",
                        if mcr & servoscope_core::machine::tml::mcr::MODE_PP != 0 {
                            "MODE PP"
                        } else {
                            "no mode"
                        },
                        if mcr & servoscope_core::machine::tml::mcr::ABSOLUTE != 0 {
                            ", CPA"
                        } else {
                            ", CPR"
                        },
                        if mcr & servoscope_core::machine::tml::mcr::TUM1 != 0 {
                            ", TUM1"
                        } else {
                            ", TUM0"
                        },
                    ))
                    .monospace(),
                );
                let rule = m.in_position_rule();
                ui.label(
                    RichText::new(format!(
                        "UPGRADE 0x{:04X}: bit 11 {} — {}",
                        upgrade & 0xFFFF,
                        u8::from(rule),
                        if rule {
                            let window = format!(
                                "motion complete waits {} tick(s) within ±{} counts",
                                (m.data[d::TONPOSOK as usize] as u16).max(1),
                                m.data[d::POSOKLIM as usize] as u16,
                            );
                            if m.profile.active {
                                format!("{window}; the profile is still moving")
                            } else if m.in_position == u16::MAX {
                                format!("{window}; in position for 65535+ ticks")
                            } else {
                                format!("{window}; in position for {} tick(s)", m.in_position)
                            }
                        } else {
                            "motion complete follows the reference".to_string()
                        }
                    ))
                    .monospace(),
                );
                ui.separator();
                ui.label(
                    RichText::new(
                        "Table A: the data of every program. Table B: EasyMotion's setup data \
                         (in the runner's JSON only when the program names them).",
                    )
                    .color(p.dim),
                );
                egui::Grid::new("tml_drive_data")
                    .striped(true)
                    .num_columns(7)
                    .show(ui, |ui| {
                        for h in [
                            "name", "value", "address", "type", "table", "access", "meaning",
                        ] {
                            ui.label(RichText::new(h).strong());
                        }
                        ui.end_row();
                        for (i, pre) in servoscope_core::machine::tml::PREDEFINED.iter().enumerate()
                        {
                            let raw =
                                m.raw(servoscope_core::machine::tml::program::Data::Pre(i as u8));
                            let name = match pre.alias {
                                Some(a) => format!("{} ({a})", pre.name),
                                None => pre.name.to_string(),
                            };
                            ui.label(RichText::new(name).monospace());
                            ui.label(RichText::new(typed_value(raw, pre.ty)).monospace());
                            ui.label(RichText::new(format!("0x{:04X}", pre.address)).monospace());
                            ui.label(pre.ty.name());
                            ui.label(if pre.table_b { "B" } else { "A" });
                            ui.label(if pre.writable { "rw" } else { "r" });
                            ui.label(RichText::new(pre.description).color(p.dim));
                            ui.end_row();
                        }
                        for ((v, &raw), address) in m
                            .program
                            .vars
                            .iter()
                            .zip(&m.vars)
                            .zip(m.program.var_addresses())
                        {
                            ui.label(RichText::new(&v.name).monospace());
                            ui.label(RichText::new(typed_value(raw, v.ty)).monospace());
                            ui.label(RichText::new(format!("0x{address:04X}")).monospace());
                            ui.label(v.ty.name());
                            ui.label("var");
                            ui.label("rw");
                            ui.label(
                                RichText::new(format!(
                                    "user variable, declared at {}",
                                    debugger.where_line(v.line)
                                ))
                                .color(p.dim),
                            );
                            ui.end_row();
                        }
                    });
            });
    }
}

/// Every label: name, where it is written and its program-memory address (spec §5.11).
pub struct LabelsPanel;

impl DialectPanel for LabelsPanel {
    fn title(&self) -> &'static str {
        "Labels"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger
            .machine_as::<Tml>()
            .is_some_and(|m| !m.program.labels.is_empty())
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Tml>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("labels_scroll")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                ui.label(
                    RichText::new(format!(
                        "Program memory from 0x4000: {} words; the end address is 0x{:04X}",
                        m.program.end_address - servoscope_core::machine::tml::PROGRAM_BASE,
                        m.program.end_address
                    ))
                    .color(p.dim),
                );
                egui::Grid::new("tml_labels")
                    .striped(true)
                    .num_columns(3)
                    .show(ui, |ui| {
                        for h in ["label", "address", "line"] {
                            ui.label(RichText::new(h).strong());
                        }
                        ui.end_row();
                        for ((name, index), &line) in
                            m.program.labels.iter().zip(&m.program.label_lines)
                        {
                            ui.label(RichText::new(name).monospace());
                            ui.label(
                                RichText::new(format!(
                                    "0x{:04X}",
                                    m.program.address_of(*index as usize)
                                ))
                                .monospace(),
                            );
                            let at = debugger.describe_line(line);
                            if ui
                                .link(RichText::new(&at).monospace())
                                .on_hover_text("Show the line")
                                .clicked()
                            {
                                out.push(Command::ShowLine(line));
                            }
                            ui.end_row();
                        }
                    });
            });
    }
}

pub struct ProductPanel;

impl DialectPanel for ProductPanel {
    fn title(&self) -> &'static str {
        "Product register"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger.machine_as::<Tml>().is_some_and(|m| {
            m.program.uses_preg
                || m.last_multiply.is_some()
                || m.program
                    .stmts
                    .iter()
                    .any(|s| matches!(s.op, servoscope_core::machine::tml::program::Op::Divide(..)))
        })
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        if let Some(m) = debugger.machine_as::<Tml>() {
            egui::ScrollArea::both()
                .id_salt("preg_scroll")
                .auto_shrink([false, false])
                .show(ui, |ui| product(ui, m, &|l| debugger.where_line(l)));
        }
    }
}

/// PREG's 48 bits, most significant first, with PRODH (47..16) above and PROD (31..0) below.
fn product(ui: &mut egui::Ui, m: &Tml, place: &dyn Fn(usize) -> String) {
    let p = palette(ui.visuals().dark_mode);
    let preg = m.preg;
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("PREG").strong().monospace());
        ui.label(RichText::new(format!("0x{preg:012X} = {}", m.preg_signed())).monospace());
    });
    let cell = vec2(11.0, 16.0);
    let gap = 3.0;
    let width = 48.0 * cell.x + 11.0 * gap;
    let (rect, _) = ui.allocate_exact_size(vec2(width, cell.y * 3.0 + 8.0), Sense::hover());
    let painter = ui.painter_at(rect.expand(1.0));
    let x_of = |bit: u32| {
        let from_left = 47 - bit;
        rect.left() + from_left as f32 * cell.x + (from_left / 4) as f32 * gap
    };
    let bits_top = rect.top() + cell.y + 4.0;
    let font = egui::FontId::monospace(11.0);
    for bit in 0..48u32 {
        let on = preg >> bit & 1 == 1;
        let x = x_of(bit);
        let r = egui::Rect::from_min_size(egui::pos2(x, bits_top), cell - vec2(1.0, 1.0));
        painter.rect_filled(r, 2.0, if on { p.bit_on } else { p.bit_off });
        painter.text(
            r.center(),
            egui::Align2::CENTER_CENTER,
            if on { "1" } else { "0" },
            font.clone(),
            if on { Color32::WHITE } else { p.dim },
        );
    }
    // The windows: PRODH over bits 47..16, PROD under bits 31..0; they share 31..16.
    let span = |hi: u32, lo: u32, y: f32, label: &str, colour: Color32| {
        let (x0, x1) = (x_of(hi), x_of(lo) + cell.x - 1.0);
        // The line stops short of its label on both sides, never through it.
        let galley =
            painter.layout_no_wrap(label.to_string(), egui::FontId::proportional(11.0), colour);
        let mid = (x0 + x1) / 2.0;
        let half = galley.size().x / 2.0 + 2.0;
        let stroke = Stroke::new(2.0, colour);
        painter.line_segment([egui::pos2(x0, y), egui::pos2(mid - half, y)], stroke);
        painter.line_segment([egui::pos2(mid + half, y), egui::pos2(x1, y)], stroke);
        painter.galley(
            egui::pos2(mid - galley.size().x / 2.0, y - galley.size().y / 2.0),
            galley,
            colour,
        );
    };
    span(
        47,
        16,
        rect.top() + cell.y / 2.0,
        " PRODH (47..16) ",
        p.label,
    );
    span(31, 0, bits_top + cell.y + 8.0, " PROD (31..0) ", p.number);
    ui.label(
        RichText::new(format!(
            "PRODH = {}   PROD = {}",
            m.raw(servoscope_core::machine::tml::program::Data::Pre(d::PRODH)) as i32,
            m.raw(servoscope_core::machine::tml::program::Data::Pre(d::PROD)) as i32
        ))
        .monospace(),
    )
    .on_hover_text(
        "A fixed × int product is 32.16: PRODH is its integer part, PROD's low half its fraction.",
    );
    ui.separator();
    if let Some(division) = servoscope_core::machine::tml::arith::division_at_pc(m) {
        crate::ui::bitrows::breakdown(ui, &division, "About to run", place, &p);
        ui.separator();
    }
    match servoscope_core::machine::tml::arith::last_multiply(m) {
        None => {
            ui.label(RichText::new("No multiply yet: `A * B << n;` fills PREG.").color(p.dim));
        }
        Some(b) => crate::ui::bitrows::breakdown(ui, &b, "Last multiply", place, &p),
    }
}

pub struct DrivePanel;

impl DialectPanel for DrivePanel {
    fn title(&self) -> &'static str {
        "Drive"
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, out: &mut Vec<Command>) {
        let Some(m) = debugger.machine_as::<Tml>() else {
            return;
        };
        let p = palette(ui.visuals().dark_mode);
        egui::ScrollArea::both()
            .id_salt("drive_scroll")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                // All sixteen inputs as switches (the toolbar shows only those in use).
                ui.horizontal_wrapped(|ui| {
                    ui.label("Inputs");
                    ui.spacing_mut().item_spacing.x = 2.0;
                    for n in 0..servoscope_core::machine::tml::INPUTS {
                        let high = m.input(n);
                        let button = egui::Button::new(RichText::new(format!("{n}")).monospace())
                            .selected(high)
                            .min_size(vec2(22.0, 18.0));
                        let r = ui.add(button).on_hover_text(format!(
                            "IN#{n} is {}: click to switch it",
                            if high { "high" } else { "low" }
                        ));
                        r.widget_info(|| {
                            egui::WidgetInfo::selected(
                                egui::Role::CheckBox,
                                true,
                                high,
                                format!("Input IN#{n}"),
                            )
                        });
                        if r.clicked()
                            && let Some(loc) = m.find(&format!("IN#{n}"))
                        {
                            out.push(Command::Debug(Action::SetInput(loc, !high)));
                        }
                    }
                });
                ui.separator();
                let event = match m.event {
                    None => "none".to_string(),
                    Some(Event::MotionComplete) => "!MC (motion complete)".into(),
                    Some(Event::Time { after, time0 }) => {
                        format!("!RT {after} (from ATIME {time0})")
                    }
                    Some(Event::Input { input, level }) => {
                        format!("!IN#{input} {}", u8::from(level))
                    }
                };
                let occurred = m.data[d::SRL as usize] & srl::EVENT != 0;
                ui.label(format!(
                    "Event: {event}{}",
                    if m.event.is_some() && occurred {
                        " — occurred"
                    } else {
                        ""
                    }
                ));
                if let Some(waited) = m.waiting() {
                    let limit = m.program.stmts.get(m.pc as usize).and_then(|s| match s.op {
                        servoscope_core::machine::tml::program::Op::Wait(t) => t,
                        _ => None,
                    });
                    let text = match limit {
                        Some(t) => format!("WAIT! waiting: {waited} of {t} ticks"),
                        None => format!("WAIT! waiting for {waited} ticks"),
                    };
                    ui.label(RichText::new(text).color(p.written));
                }
                let profile = &m.profile;
                ui.label(format!(
                    "Profile: {}{}  end {}  {}  TUM{}",
                    if m.mode_pp { "MODE PP" } else { "no mode" },
                    if profile.stopping {
                        ", stopping"
                    } else if profile.active {
                        ", moving"
                    } else {
                        ""
                    },
                    profile.end,
                    if m.relative { "CPR" } else { "CPA" },
                    u8::from(m.tum1)
                ))
                .on_hover_text(format!(
                    "speed {} and acceleration {} counts/tick",
                    q16_exact(profile.speed),
                    q16_exact(profile.accel)
                ));
                let (mer_bits, der_bits) = (m.data[d::MER as usize], m.data[d::DER as usize]);
                if mer_bits & mer::COMMAND_ERROR != 0 {
                    let mut why = Vec::new();
                    if der_bits & der::STACK_OVERFLOW != 0 {
                        why.push("stack overflow");
                    }
                    if der_bits & der::STACK_UNDERFLOW != 0 {
                        why.push("stack underflow");
                    }
                    if der_bits & der::UPD_IGNORED != 0 {
                        why.push("UPD ignored");
                    }
                    ui.label(
                        RichText::new(format!("Command error: {}", why.join(", "))).color(p.error),
                    );
                }
                ui.separator();
                let lines = m.call_stack_lines();
                ui.label(format!("Call stack ({} of {STACK_DEPTH})", lines.len()));
                if lines.is_empty() {
                    ui.label(RichText::new("empty").color(p.dim));
                }
                for (depth, (line, &back)) in lines.iter().zip(&m.stack).enumerate().rev() {
                    ui.label(
                        RichText::new(format!(
                            "{depth}: CALL at {}, returns to 0x{:04X}",
                            debugger.where_line(*line),
                            m.program.address_of(back as usize)
                        ))
                        .monospace(),
                    );
                }
            });
    }
}

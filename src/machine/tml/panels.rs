//! TML's own panels (built with the window only): the product register bit by bit with its
//! PROD and PRODH windows and the last multiply, and the drive's program state (call stack,
//! event and WAIT!, error bits).

use egui::{Color32, RichText, Sense, Stroke, vec2};

use super::{Event, STACK_DEPTH, Tml, d, der, mer, srl};
use crate::debugger::Debugger;
use crate::machine::MachineView;
use crate::machine::value::q16_exact;
use crate::ui::Command;
use crate::ui::panels::DialectPanel;
use crate::ui::theme::palette;

pub fn panels() -> Vec<Box<dyn DialectPanel>> {
    vec![Box::new(ProductPanel), Box::new(DrivePanel)]
}

pub struct ProductPanel;

impl DialectPanel for ProductPanel {
    fn title(&self) -> &'static str {
        "Product register"
    }
    fn has_content(&self, debugger: &Debugger) -> bool {
        debugger
            .machine_as::<Tml>()
            .is_some_and(|m| {
                m.program.uses_preg
                    || m.last_multiply.is_some()
                    || m.program
                        .stmts
                        .iter()
                        .any(|s| matches!(s.op, super::program::Op::Divide(..)))
            })
    }
    fn show(&mut self, ui: &mut egui::Ui, debugger: &Debugger, _: f32, _: &mut Vec<Command>) {
        if let Some(m) = debugger.machine_as::<Tml>() {
            egui::ScrollArea::both()
                .id_salt("preg_scroll")
                .auto_shrink([false, false])
                .show(ui, |ui| product(ui, m));
        }
    }
}

/// PREG's 48 bits, most significant first, with PRODH (47..16) above and PROD (31..0) below.
fn product(ui: &mut egui::Ui, m: &Tml) {
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
    span(47, 16, rect.top() + cell.y / 2.0, " PRODH (47..16) ", p.label);
    span(31, 0, bits_top + cell.y + 8.0, " PROD (31..0) ", p.number);
    ui.label(
        RichText::new(format!(
            "PRODH = {}   PROD = {}",
            m.raw(super::program::Data::Pre(d::PRODH)) as i32,
            m.raw(super::program::Data::Pre(d::PROD)) as i32
        ))
        .monospace(),
    )
    .on_hover_text("A fixed × int product is 32.16: PRODH is its integer part, PROD's low half its fraction.");
    ui.separator();
    if let Some(division) = super::arith::division_at_pc(m) {
        crate::ui::bitrows::breakdown(ui, &division, "About to run", &p);
        ui.separator();
    }
    match super::arith::last_multiply(m) {
        None => {
            ui.label(RichText::new("No multiply yet: `A * B << n;` fills PREG.").color(p.dim));
        }
        Some(b) => crate::ui::bitrows::breakdown(ui, &b, "Last multiply", &p),
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
                    for n in 0..super::INPUTS {
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
                            out.push(Command::SetInput(loc, !high));
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
                    let limit = m
                        .program
                        .stmts
                        .get(m.pc as usize)
                        .and_then(|s| match s.op {
                            super::program::Op::Wait(t) => t,
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
                        RichText::new(format!("Command error: {}", why.join(", ")))
                            .color(p.error),
                    );
                }
                ui.separator();
                let lines = m.call_stack_lines();
                ui.label(format!("Call stack ({} of {STACK_DEPTH})", lines.len()));
                if lines.is_empty() {
                    ui.label(RichText::new("empty").color(p.dim));
                }
                for (depth, line) in lines.iter().enumerate().rev() {
                    ui.label(
                        RichText::new(format!("{depth}: CALL on line {line}")).monospace(),
                    );
                }
            });
    }
}

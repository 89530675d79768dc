//! The trace's channels against time: any locations the user picks (each dialect has defaults:
//! SilverLode plots target and actual position, and the error below). Channels of one group
//! share a plot; groups are stacked with linked time axes.
//!
//! egui_plot draws what it is given, so each channel is decimated by the trace to at most two
//! points per pixel column of the visible range, and cached until the range, the width or the
//! trace changes. The view follows the newest data until the user zooms or pans; "Reset view"
//! follows again.

use egui::{Color32, RichText};
use egui_plot::{AxisHints, Legend, Line, Plot, PlotPoints, VLine};

use super::Command;
use super::theme::{Palette, palette};
use crate::debugger::trace::{Channel, MAX_CHANNELS, Trace};
use crate::debugger::{ChannelChoice, Debugger};

#[derive(Clone, Copy, PartialEq)]
struct CacheKey {
    channel: usize,
    x0: f64,
    x1: f64,
    columns: usize,
    len: usize,
    end: Option<u64>,
}

pub struct PlotView {
    /// The x range follows the newest data.
    pub following: bool,
    /// The tick the user clicked, with its values shown under the plot.
    pub selected_tick: Option<u64>,
    /// The tick under the pointer.
    pub hovered_tick: Option<u64>,
    /// The location typed in the channel editor.
    pub new_channel: String,
    pub channel_error: Option<String>,
    cache: Vec<(CacheKey, Vec<[f64; 2]>)>,
    reset_requested: bool,
}

impl Default for PlotView {
    fn default() -> Self {
        PlotView {
            following: true,
            selected_tick: None,
            hovered_tick: None,
            new_channel: String::new(),
            channel_error: None,
            cache: Vec::new(),
            reset_requested: false,
        }
    }
}

impl PlotView {
    /// The decimated channel for this view, from the cache when nothing changed.
    fn points(
        &mut self,
        trace: &Trace,
        channel: usize,
        x0: f64,
        x1: f64,
        columns: usize,
    ) -> Vec<[f64; 2]> {
        let key = CacheKey {
            channel,
            x0,
            x1,
            columns,
            len: trace.len(),
            end: trace.end_tick(),
        };
        if let Some((_, points)) = self.cache.iter().find(|(k, _)| *k == key) {
            return points.clone();
        }
        let points = trace.decimate(channel, x0, x1, columns);
        self.cache.retain(|(k, _)| k.channel != channel);
        self.cache.push((key, points.clone()));
        points
    }

    pub fn reset(&mut self) {
        self.following = true;
        self.reset_requested = true;
        self.cache.clear();
    }
}

fn colour(p: &Palette, index: usize) -> Color32 {
    [
        p.mnemonic,
        p.written,
        p.error,
        p.operation,
        p.number,
        p.label,
        p.condition,
        p.register,
    ][index % 8]
}

fn ms_axis<'a>(tick_micros: f64) -> AxisHints<'a> {
    AxisHints::new_x()
        .label("time (ms)")
        .formatter(move |mark, _range| format!("{:.1}", mark.value * tick_micros / 1000.0))
}

fn readout(trace: &Trace, channels: &[Channel], tick: u64, micros: f64) -> Option<String> {
    let s = trace.at(tick)?;
    let values: Vec<String> = channels
        .iter()
        .enumerate()
        .map(|(i, c)| format!("{} {}", c.label, s.get(i)))
        .collect();
    Some(format!(
        "tick {tick} ({:.3} ms): {}",
        tick as f64 * micros / 1000.0,
        values.join("  ")
    ))
}

/// The channel list with remove buttons, and a field to add one.
fn channel_editor(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut PlotView,
    out: &mut Vec<Command>,
) {
    let chosen = debugger.channel_choices().to_vec();
    for (i, c) in chosen.iter().enumerate() {
        ui.horizontal(|ui| {
            let missing = debugger.find(&c.location).is_none();
            let mut text = RichText::new(format!("{} — {}", c.location, c.label));
            if missing {
                text = text.strikethrough();
            }
            ui.label(text).on_hover_text(if missing {
                "This program has no such location"
            } else {
                "Recorded on every tick"
            });
            let mut group = c.group;
            egui::ComboBox::new(("channel_group", i), "")
                .selected_text(format!("plot {}", group + 1))
                .show_ui(ui, |ui| {
                    for g in 0..4u8 {
                        ui.selectable_value(&mut group, g, format!("plot {}", g + 1));
                    }
                });
            if group != c.group {
                let mut next = chosen.clone();
                next[i].group = group;
                out.push(Command::SetChannels(next));
            }
            if ui
                .small_button("Remove")
                .on_hover_text(format!("Stop plotting {}", c.location))
                .clicked()
            {
                let mut next = chosen.clone();
                next.remove(i);
                out.push(Command::SetChannels(next));
            }
        });
    }
    ui.horizontal(|ui| {
        let label = ui.label("Add channel");
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut view.new_channel)
                    .desired_width(90.0)
                    .hint_text("R7, ACC, …"),
            )
            .labelled_by(label.id);
        let entered = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Add").clicked() || entered {
            let name = view.new_channel.trim().to_string();
            view.channel_error = match debugger.find(&name) {
                _ if chosen.len() >= MAX_CHANNELS => {
                    Some(format!("at most {MAX_CHANNELS} channels"))
                }
                None => Some(format!("this program has no location '{name}'")),
                Some(loc) => {
                    let canonical = debugger
                        .machine()
                        .info(loc)
                        .map_or(name.clone(), |i| i.name);
                    let mut next = chosen.clone();
                    next.push(ChannelChoice {
                        label: canonical.clone(),
                        location: canonical,
                        group: chosen.iter().map(|c| c.group + 1).max().unwrap_or(0).min(3),
                    });
                    out.push(Command::SetChannels(next));
                    view.new_channel.clear();
                    None
                }
            };
        }
    });
    if let Some(e) = &view.channel_error {
        ui.label(RichText::new(e).color(palette(ui.visuals().dark_mode).error));
    }
}

pub fn show(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    view: &mut PlotView,
    height: f32,
    out: &mut Vec<Command>,
) {
    let p = palette(ui.visuals().dark_mode);
    let trace = debugger.trace();
    let channels = debugger.channels();
    let machine = debugger.machine();
    let now = machine.ticks();
    let micros = f64::from(machine.tick_micros());
    let ticks_word = debugger.dialect().vocabulary.tick;
    ui.horizontal(|ui| {
        ui.strong("Plot");
        if ui
            .button("Reset view")
            .on_hover_text("Show everything and follow the newest data")
            .clicked()
        {
            view.reset();
        }
        ui.menu_button("Channels", |ui| channel_editor(ui, debugger, view, out));
        if ui.button("Export CSV…").clicked() {
            out.push(Command::ExportDialog);
        }
        if !view.following {
            ui.label(RichText::new("zoomed: not following").small().color(p.dim));
        }
        if trace.dropped() > 0 {
            ui.label(
                RichText::new(format!(
                    "trace starts at {ticks_word} {}",
                    trace.first_tick().unwrap_or(0)
                ))
                .small()
                .color(p.dim),
            )
            .on_hover_text("The trace keeps the newest 16 M changes; older ones were dropped.");
        }
    });
    if channels.is_empty() {
        ui.label(
            RichText::new("No channels: add a location under Channels to plot it.").color(p.dim),
        );
        return;
    }

    let mut groups: Vec<u8> = channels.iter().map(|c| c.group).collect();
    groups.sort_unstable();
    groups.dedup();
    let first = trace.first_tick().unwrap_or(0) as f64;
    let furthest = debugger.furthest_tick();
    let follow_range = (first, (furthest as f64).max(first + 100.0));
    let link = ui.scope_id().with("plot_x_link");
    // Header and readout lines take about 50 px of the panel; the first plot gets more room.
    let height = (height - 50.0).max(150.0);
    let rows = groups.len() as f32;
    let main_height = if rows > 1.0 {
        (height * 0.5).max(80.0)
    } else {
        height
    };
    let small_height = if rows > 1.0 {
        ((height - main_height) / (rows - 1.0) - 8.0).max(50.0)
    } else {
        0.0
    };
    let reset = std::mem::take(&mut view.reset_requested);
    let mut hovered = None;
    let mut clicked = None;
    let mut user_moved = false;

    for (row, &group) in groups.iter().enumerate() {
        let members: Vec<(usize, &Channel)> = channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.group == group)
            .collect();
        let last = row + 1 == groups.len();
        let axis_label = members
            .iter()
            .map(|(_, c)| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ");
        let mut plot = Plot::new(("plot", group))
            .height(if row == 0 { main_height } else { small_height })
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            .auto_bounds([false, true])
            .y_axis_label(axis_label)
            .allow_double_click_reset(false)
            .show_x(false)
            .show_y(false);
        // One channel needs no legend: the axis label names it.
        if members.len() > 1 {
            plot = plot.legend(Legend::default().position(egui_plot::Corner::LeftTop));
        }
        plot = if last {
            plot.custom_x_axes(vec![AxisHints::new_x().label(ticks_word), ms_axis(micros)])
        } else {
            plot.show_axes([false, true])
        };
        if reset {
            plot = plot.reset();
        }
        let response = plot.show(ui, |plot_ui| {
            if view.following || reset {
                plot_ui.set_plot_bounds_x(follow_range.0..=follow_range.1);
            }
            let bounds = plot_ui.plot_bounds();
            let (x0, x1) = (bounds.min()[0], bounds.max()[0]);
            let columns = plot_ui.response().rect.width().max(1.0) as usize;
            for &(index, channel) in &members {
                let points = view.points(trace, index, x0, x1, columns);
                plot_ui.line(
                    Line::new(channel.label.as_str(), PlotPoints::from(points))
                        .color(colour(&p, index))
                        .width(1.5),
                );
            }
            plot_ui.vline(
                VLine::new("", now as f64)
                    .color(p.text.gamma_multiply(0.6))
                    .width(1.0),
            );
            if let Some(t) = view.selected_tick {
                plot_ui.vline(VLine::new("", t as f64).color(p.dim).width(1.0));
            }
            plot_ui.pointer_coordinate()
        });
        let r = &response.response;
        if r.dragged()
            || (r.hovered()
                && ui.input(|i| i.smooth_scroll_delta != egui::Vec2::ZERO || i.zoom_delta() != 1.0))
        {
            user_moved = true;
        }
        if let Some(pos) = response.inner {
            if r.hovered() && pos.x >= 0.0 {
                hovered = Some(pos.x.round() as u64);
            }
            if r.clicked() && pos.x >= 0.0 {
                clicked = Some(pos.x.round() as u64);
            }
        }
    }
    if user_moved {
        view.following = false;
    }
    view.hovered_tick = hovered;
    if let Some(t) = clicked {
        // Clicking the plot selects that tick and goes there.
        let t = t.min(debugger.furthest_tick());
        view.selected_tick = Some(t);
        out.push(Command::GoToTick(t));
    }
    let text = view
        .hovered_tick
        .and_then(|t| readout(trace, channels, t.min(furthest), micros))
        .or_else(|| {
            view.selected_tick
                .and_then(|t| readout(trace, channels, t, micros))
                .map(|r| format!("selected {r}"))
        })
        .unwrap_or_else(|| {
            format!("Hover the plot to read values; click to go to that {ticks_word}.")
        });
    ui.label(RichText::new(text).monospace().small());
}

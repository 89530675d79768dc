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
use servoscope_core::debugger::Action;

use super::Command;
use super::theme::{Palette, palette};
use servoscope_core::debugger::trace::{Channel, MAX_CHANNELS, PLOT_GROUPS, Trace};
use servoscope_core::debugger::{ChannelChoice, Debugger};

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
    /// What each stacked plot showed last frame, top to bottom.
    pub frames: Vec<PlotFrame>,
}

/// Where a plot drew its data and which ranges it showed. The plots share one time scale, so
/// their frames share their left and right edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlotFrame {
    pub rect: egui::Rect,
    pub x: (f64, f64),
    pub y: (f64, f64),
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
            frames: Vec::new(),
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

/// Labels need about this much room apart; egui_plot's default (60 px) leaves short traces
/// with a single label.
const X_LABEL_SPACING: std::ops::RangeInclusive<f32> = 44.0..=64.0;

fn ms_axis<'a>(tick_micros: f64) -> AxisHints<'a> {
    AxisHints::new_x()
        .label("time (ms)")
        .label_spacing(X_LABEL_SPACING)
        .formatter(move |mark, _range| compact(mark.value * tick_micros / 1000.0))
}

/// Grid steps in a 1–2–5 sequence (egui_plot's default steps by 10, so a plot a few hundred
/// pixels wide often has room for a single label).
fn steps_125(input: egui_plot::GridInput) -> [f64; 3] {
    let base = input.base_step_size.max(f64::MIN_POSITIVE);
    let decade = 10f64.powf(base.log10().floor());
    let unit = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= base)
        .unwrap_or(10.0 * decade);
    let mantissa = (unit / 10f64.powf(unit.log10().floor())).round();
    // Each step a multiple of the one before, so the thicker lines fall on thinner ones.
    match mantissa as u8 {
        2 => [unit, unit * 5.0, unit * 10.0],
        5 => [unit, unit * 2.0, unit * 10.0],
        _ => [unit, unit * 5.0, unit * 10.0],
    }
}

/// One time axis (ticks, or ms) under the last plot. egui_plot drops a plot's axes altogether
/// when they leave no room for data, so their room is set aside first.
const X_AXIS_HEIGHT: f32 = 34.0;
/// Below this pane height the readout line goes into a tooltip.
const READOUT_LINE_FROM: f32 = 200.0;
/// Room right of the plot for half the last time label.
const PLOT_RIGHT_MARGIN: f32 = 14.0;
const PLOT_LEFT_MARGIN: f32 = 3.0;

/// Below this panel height only the tick axis is drawn (the readout still gives ms).
const BOTH_AXES_FROM: f32 = 260.0;

/// Every plot's y axis is this wide, so the plots' data areas line up under each other.
const Y_AXIS_WIDTH: f32 = 78.0;

/// A y-axis label that fits [`Y_AXIS_WIDTH`]: large values with a k/M/G suffix.
fn compact(value: f64) -> String {
    let magnitude = value.abs();
    let (scaled, suffix) = if magnitude >= 1e9 {
        (value / 1e9, "G")
    } else if magnitude >= 1e6 {
        (value / 1e6, "M")
    } else if magnitude >= 1e4 {
        (value / 1e3, "k")
    } else {
        return if value.fract() == 0.0 {
            format!("{value:.0}")
        } else {
            format!("{value:.2}")
        };
    };
    let text = format!("{scaled:.2}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    format!("{text}{suffix}")
}

/// The y range that shows `values`: 5 % of margin around them; a constant value gets a small
/// range of its own (at least ±1) instead of egui_plot's huge default.
pub fn y_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span < 1.0 {
        let pad = (lo.abs() * 0.05).max(1.0);
        return (lo - pad, hi + pad);
    }
    (lo - span * 0.05, hi + span * 0.05)
}

fn readout(trace: &Trace, channels: &[Channel], tick: u64, micros: f64) -> Option<String> {
    let s = trace.at(tick)?;
    let values: Vec<String> = channels
        .iter()
        .enumerate()
        .map(|(i, c)| match c.reading_name() {
            Some(reading) => format!("{} {} ({reading})", c.label, c.value_text(s.get(i))),
            None => format!("{} {}", c.label, s.get(i)),
        })
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
            // The plot as buttons, not a combo box: a combo's own popup inside this popup
            // would close both on a click.
            let mut group = c.group;
            ui.label("plot");
            for g in 0..PLOT_GROUPS {
                ui.selectable_value(&mut group, g, format!("{}", g + 1))
                    .on_hover_text(format!("Draw {} on plot {}", c.location, g + 1))
                    .widget_info(|| {
                        egui::WidgetInfo::selected(
                            egui::Role::Button,
                            true,
                            g == c.group,
                            format!("{} on plot {}", c.location, g + 1),
                        )
                    });
            }
            if group != c.group {
                let mut next = chosen.clone();
                next[i].group = group;
                out.push(Command::Debug(Action::SetChannels(next)));
            }
            if ui
                .small_button("Remove")
                .on_hover_text(format!("Stop plotting {}", c.location))
                .clicked()
            {
                let mut next = chosen.clone();
                next.remove(i);
                out.push(Command::Debug(Action::SetChannels(next)));
            }
        });
    }
    ui.horizontal(|ui| {
        let label = ui.label("Add channel");
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut view.new_channel)
                    .char_limit(servoscope_core::session::limits::TEXT)
                    .desired_width(90.0)
                    .hint_text(format!(
                        "{}, …",
                        debugger.dialect().vocabulary.location_hint
                    )),
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
                        group: chosen
                            .iter()
                            .map(|c| c.group.saturating_add(1))
                            .max()
                            .unwrap_or(0)
                            .min(PLOT_GROUPS - 1),
                    });
                    out.push(Command::Debug(Action::SetChannels(next)));
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

pub fn show(ui: &mut egui::Ui, debugger: &Debugger, view: &mut PlotView, out: &mut Vec<Command>) {
    let p = palette(ui.visuals().dark_mode);
    let trace = debugger.trace();
    let channels = debugger.channels();
    let machine = debugger.machine();
    let now = machine.ticks();
    let micros = f64::from(machine.tick_micros());
    let ticks_word = debugger.dialect().vocabulary.tick;
    // In a narrow pane the buttons take short names, so they stay on one row above the plot.
    let narrow = ui.available_width() < 300.0;
    ui.horizontal_wrapped(|ui| {
        if ui
            .button(if narrow { "Fit" } else { "Reset view" })
            .on_hover_text("Show everything and follow the newest data")
            .clicked()
        {
            view.reset();
        }
        super::form_menu_button(ui, "Channels", |ui| channel_editor(ui, debugger, view, out));
        if ui
            .button(if narrow { "CSV…" } else { "Export CSV…" })
            .on_hover_text("Export the plotted channels as CSV")
            .clicked()
        {
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
    // A little room after the newest tick, so its label is not cut at the edge.
    let last = (furthest as f64).max(first + 100.0);
    let follow_range = (first, last + (last - first) * 0.03);
    let link = ui.scope_id().with("plot_x_link");
    // The plots share what is left under the header, less the readout line below; the first
    // gets the most room. Nothing is drawn past the panel's edge.
    let rows = groups.len() as f32;
    let spacing = ui.spacing().item_spacing.y;
    // A short pane gives the readout line's room to the plot; hovering still reads values,
    // in a tooltip.
    let readout_line = ui.available_height() >= READOUT_LINE_FROM;
    let readout_height = if readout_line {
        ui.fonts_mut(|f| f.row_height(&egui::FontId::monospace(12.0))) + spacing
    } else {
        0.0
    };
    let both_axes = ui.available_height() >= BOTH_AXES_FROM;
    let x_axes_height = if both_axes { 2.0 } else { 1.0 } * X_AXIS_HEIGHT;
    let room = (ui.available_height() - readout_height - spacing * rows - x_axes_height).max(0.0);
    // Heights of the data areas; the last plot also carries the two time axes.
    let (main_height, small_height) = if rows > 1.0 {
        let main = room * 0.55;
        (main.max(24.0), ((room - main) / (rows - 1.0)).max(24.0))
    } else {
        (room.max(24.0), 0.0)
    };
    let reset = std::mem::take(&mut view.reset_requested);
    let mut frames = Vec::new();
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
            .map(|(_, c)| match c.reading_name() {
                Some(reading) => format!("{} ({reading})", c.name),
                None => c.name.clone(),
            })
            .collect::<Vec<_>>()
            .join(", ");
        let mut plot = Plot::new(("plot", group))
            .height(
                if row == 0 { main_height } else { small_height }
                    + if last { x_axes_height } else { 0.0 },
            )
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            // y always fits the data in view: the wheel, drags and Ctrl+wheel act on time only;
            // a box drawn with the right button zooms to that time span.
            .auto_bounds([false, false])
            .allow_zoom([true, false])
            .allow_scroll([true, false])
            .allow_drag([true, false])
            .allow_boxed_zoom(true)
            .x_grid_spacer(egui_plot::uniform_grid_spacer(steps_125))
            .y_grid_spacer(egui_plot::uniform_grid_spacer(steps_125))
            .y_axis_min_width(Y_AXIS_WIDTH)
            .y_axis_formatter(|mark, _| compact(mark.value))
            .y_axis_label(axis_label)
            .allow_double_click_reset(false)
            .show_x(false)
            .show_y(false);
        // One channel needs no legend: the axis label names it.
        let plot_height = if row == 0 { main_height } else { small_height };
        // A legend in a plot this short would hide its data.
        if members.len() > 1 && plot_height >= 80.0 {
            // See-through, so a curve under the legend still shows.
            plot = plot.legend(
                Legend::default()
                    .position(egui_plot::Corner::LeftTop)
                    .background_alpha(0.35),
            );
        }
        plot = if last {
            let mut axes = vec![
                // Nine-digit tick numbers side by side would run together: 100M, 200M.
                AxisHints::new_x()
                    .label(ticks_word)
                    .label_spacing(X_LABEL_SPACING)
                    .formatter(|mark, _range| compact(mark.value)),
            ];
            if both_axes {
                axes.push(ms_axis(micros));
            }
            plot.custom_x_axes(axes)
        } else {
            plot.show_axes([false, true])
        };
        if reset {
            plot = plot.reset();
        }
        // Room at the right for the last time label, which is centred on its tick.
        plot = plot.width((ui.available_width() - PLOT_RIGHT_MARGIN - PLOT_LEFT_MARGIN).max(60.0));
        // And a little at the left, where the rotated axis label's first letter would touch
        // the pane's edge.
        let response = ui
            .horizontal(|ui| {
                ui.spacing_mut().item_spacing.x = 0.0;
                ui.add_space(PLOT_LEFT_MARGIN);
                plot.show(ui, |plot_ui| {
                    if view.following || reset {
                        plot_ui.set_plot_bounds_x(follow_range.0..=follow_range.1);
                    }
                    // A plain mouse wheel only scrolls up and down: here that moves along time (y is
                    // never scrolled, it fits the data).
                    let (wheel, zooming) = plot_ui.ctx().input(|i| {
                        (
                            i.smooth_scroll_delta.y,
                            i.modifiers.command || i.modifiers.ctrl,
                        )
                    });
                    if wheel != 0.0 && !zooming && plot_ui.response().hovered() {
                        plot_ui.translate_bounds(egui::vec2(wheel, 0.0));
                    }
                    let bounds = plot_ui.plot_bounds();
                    let (x0, x1) = (bounds.min()[0], bounds.max()[0]);
                    let columns = plot_ui.response().rect.width().max(1.0) as usize;
                    let lines: Vec<(usize, &Channel, Vec<[f64; 2]>)> = members
                        .iter()
                        .map(|&(index, channel)| {
                            let mut points = view.points(trace, index, x0, x1, columns);
                            // Decimated on the stored integers (BCD and Q16.16 keep their order), drawn
                            // in the location's reading.
                            if channel.reading_name().is_some() {
                                for p in &mut points {
                                    p[1] = channel.plotted(p[1] as i64);
                                }
                            }
                            (index, channel, points)
                        })
                        .collect();
                    let markers = if row == 0 {
                        machine
                            .as_motion()
                            .map(|m| m.plot_markers())
                            .unwrap_or_default()
                    } else {
                        Vec::new()
                    };
                    let range = y_range(
                        lines
                            .iter()
                            .flat_map(|(_, _, pts)| pts.iter().map(|p| p[1]))
                            .chain(markers.iter().map(|(_, v)| *v as f64)),
                    );
                    // The in-position window around its channel (TML: TPOS ± POSOKLIM).
                    if let Some((name, half, label)) =
                        machine.as_motion().and_then(|m| m.plot_band())
                        && let Some((_, _, points)) = lines
                            .iter()
                            .find(|(_, c, _)| c.expr.is_none() && c.name == name)
                    {
                        for (sign, title) in [(1.0, label.as_str()), (-1.0, "")] {
                            let shifted: Vec<[f64; 2]> = points
                                .iter()
                                .map(|p| [p[0], p[1] + sign * half as f64])
                                .collect();
                            plot_ui.line(
                                Line::new(title, PlotPoints::from(shifted))
                                    .color(p.written.gamma_multiply(0.6))
                                    .style(egui_plot::LineStyle::dotted_dense())
                                    .width(1.0),
                            );
                        }
                    }
                    for (label, value) in &markers {
                        plot_ui.hline(
                            egui_plot::HLine::new(label.as_str(), *value as f64)
                                .color(p.dim)
                                .style(egui_plot::LineStyle::dashed_loose()),
                        );
                    }
                    plot_ui.set_plot_bounds_y(range.0..=range.1);
                    frames.push(PlotFrame {
                        rect: *plot_ui.transform().frame(),
                        x: (x0, x1),
                        y: range,
                    });
                    for (index, channel, points) in lines {
                        plot_ui.line(
                            Line::new(channel.titled(), PlotPoints::from(points))
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
                })
            })
            .inner;
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
    view.frames = frames;
    if user_moved {
        view.following = false;
    }
    view.hovered_tick = hovered;
    if let Some(t) = clicked {
        // Clicking the plot selects that tick and goes there.
        let t = t.min(debugger.furthest_tick());
        view.selected_tick = Some(t);
        out.push(Command::Debug(Action::GoToTick(t)));
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
    if readout_line {
        ui.label(RichText::new(text).monospace().size(12.0));
    } else if hovered.is_some() {
        egui::Tooltip::always_open(
            ui.ctx().clone(),
            ui.layer_id(),
            egui::Id::unique("plot_readout"),
            egui::PopupAnchor::Pointer,
        )
        .show(|ui| ui.label(RichText::new(text).monospace().size(12.0)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_range_pads_data_and_gives_constants_a_range() {
        assert_eq!(y_range([0.0, 0.0]), (-1.0, 1.0));
        assert_eq!(y_range([]), (-1.0, 1.0));
        assert_eq!(y_range([f64::NAN]), (-1.0, 1.0));
        assert_eq!(y_range([1000.0]), (950.0, 1050.0));
        assert_eq!(y_range([-5.0]), (-6.0, -4.0));
        assert_eq!(y_range([0.0, 100.0, 50.0]), (-5.0, 105.0));
    }

    #[test]
    fn axis_labels_stay_short() {
        assert_eq!(compact(0.0), "0");
        assert_eq!(compact(-2500.0), "-2500");
        assert_eq!(compact(0.5), "0.50");
        assert_eq!(compact(30_000_000.0), "30M");
        assert_eq!(compact(-1_250_000.0), "-1.25M");
        assert_eq!(compact(12_000.0), "12k");
        assert_eq!(compact(2_147_483_647.0), "2.15G");
    }

    #[test]
    fn grid_steps_run_one_two_five() {
        let steps = |base| {
            steps_125(egui_plot::GridInput {
                bounds: (0.0, 1.0),
                base_step_size: base,
            })
        };
        assert_eq!(steps(1.0), [1.0, 5.0, 10.0]);
        assert_eq!(steps(1.5), [2.0, 10.0, 20.0]);
        assert_eq!(steps(3.0), [5.0, 10.0, 50.0]);
        assert_eq!(steps(7.0), [10.0, 50.0, 100.0]);
        assert_eq!(steps(120.0), [200.0, 1000.0, 2000.0]);
    }
}

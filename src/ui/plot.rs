//! Target versus actual position against time, the position error below, velocity optional.
//!
//! egui_plot draws what it is given, so each series is decimated by the trace to at most two
//! points per pixel column of the visible range, and cached until the range, the width or the
//! trace changes. The view follows the newest data until the user zooms or pans; "Reset view"
//! follows again.

use egui::{Color32, RichText};
use egui_plot::{AxisHints, Legend, Line, Plot, PlotPoints, VLine};

use super::Command;
use super::theme::palette;
use crate::debugger::Debugger;
use crate::debugger::trace::{Series, Trace};
use crate::machine::Machine;

/// Native velocity units (counts/tick × 2^26) to counts per second.
const VELOCITY_TO_COUNTS_PER_S: f64 = 1.0 / 67_108_864.0 / 120e-6;

#[derive(Clone, Copy, PartialEq)]
struct CacheKey {
    series: Series,
    x0: f64,
    x1: f64,
    columns: usize,
    len: usize,
    end: Option<u64>,
}

pub struct PlotView {
    /// The x range follows the newest data.
    pub following: bool,
    pub show_velocity: bool,
    /// The tick the user clicked, with its values shown under the plot.
    pub selected_tick: Option<u64>,
    /// The tick under the pointer.
    pub hovered_tick: Option<u64>,
    cache: Vec<(CacheKey, Vec<[f64; 2]>)>,
    reset_requested: bool,
}

impl Default for PlotView {
    fn default() -> Self {
        PlotView {
            following: true,
            show_velocity: false,
            selected_tick: None,
            hovered_tick: None,
            cache: Vec::new(),
            reset_requested: false,
        }
    }
}

impl PlotView {
    /// The decimated series for this view, from the cache when nothing changed.
    fn points(
        &mut self,
        trace: &Trace,
        series: Series,
        x0: f64,
        x1: f64,
        columns: usize,
    ) -> Vec<[f64; 2]> {
        let key = CacheKey {
            series,
            x0,
            x1,
            columns,
            len: trace.len(),
            end: trace.end_tick(),
        };
        if let Some((_, points)) = self.cache.iter().find(|(k, _)| *k == key) {
            return points.clone();
        }
        let mut points = trace.decimate(series, x0, x1, columns);
        if series == Series::Velocity {
            points
                .iter_mut()
                .for_each(|p| p[1] *= VELOCITY_TO_COUNTS_PER_S);
        }
        self.cache.retain(|(k, _)| k.series != series);
        self.cache.push((key, points.clone()));
        points
    }

    pub fn reset(&mut self) {
        self.following = true;
        self.reset_requested = true;
        self.cache.clear();
    }
}

fn ms_axis<'a>(tick_micros: f64) -> AxisHints<'a> {
    AxisHints::new_x()
        .label("time (ms)")
        .formatter(move |mark, _range| format!("{:.1}", mark.value * tick_micros / 1000.0))
}

fn readout(trace: &Trace, tick: u64, micros: f64) -> Option<String> {
    let s = trace.at(tick)?;
    Some(format!(
        "tick {tick} ({:.3} ms): target {}  actual {}  error {}  velocity {:.0} counts/s",
        tick as f64 * micros / 1000.0,
        s.values[0],
        s.values[1],
        s.values[2],
        f64::from(s.values[3]) * VELOCITY_TO_COUNTS_PER_S
    ))
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
    let machine = debugger.machine();
    let now = machine.ticks();
    let micros = f64::from(machine.tick_micros());
    ui.horizontal(|ui| {
        ui.strong("Position");
        if ui
            .button("Reset view")
            .on_hover_text("Show everything and follow the newest data")
            .clicked()
        {
            view.reset();
        }
        ui.checkbox(&mut view.show_velocity, "Velocity");
        if ui.button("Export CSV…").clicked() {
            out.push(Command::ExportDialog);
        }
        if !view.following {
            ui.label(RichText::new("zoomed: not following").small().color(p.dim));
        }
        if trace.dropped() > 0 {
            ui.label(
                RichText::new(format!(
                    "trace starts at tick {}",
                    trace.first_tick().unwrap_or(0)
                ))
                .small()
                .color(p.dim),
            )
            .on_hover_text("The trace keeps the newest 16 M changes; older ones were dropped.");
        }
    });

    let first = trace.first_tick().unwrap_or(0) as f64;
    let furthest = debugger.furthest_tick();
    let follow_range = (first, (furthest as f64).max(first + 100.0));
    let link = ui.scope_id().with("plot_x_link");
    // Header and readout lines take about 50 px of the panel.
    let height = (height - 50.0).max(150.0);
    let rows = if view.show_velocity { 3.0 } else { 2.0 };
    let main_height = (height * if rows > 2.0 { 0.42 } else { 0.5 }).max(80.0);
    let small_height = ((height - main_height) / (rows - 1.0) - 8.0).max(50.0);
    let reset = std::mem::take(&mut view.reset_requested);
    let show_velocity = view.show_velocity;
    let mut hovered = None;
    let mut clicked = None;
    let mut user_moved = false;

    let mut panel = |ui: &mut egui::Ui,
                     id: &str,
                     height: f32,
                     series: &[(Series, Color32)],
                     axis_label: &str,
                     x_axis: bool| {
        let mut plot = Plot::new(id)
            .height(height)
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            .auto_bounds([false, true])
            .y_axis_label(axis_label)
            .allow_double_click_reset(false)
            .show_x(false)
            .show_y(false);
        // One series needs no legend: the axis label names it.
        if series.len() > 1 {
            plot = plot.legend(Legend::default().position(egui_plot::Corner::LeftTop));
        }
        plot = if x_axis {
            plot.custom_x_axes(vec![AxisHints::new_x().label("tick"), ms_axis(micros)])
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
            for &(s, colour) in series {
                let points = view.points(trace, s, x0, x1, columns);
                plot_ui.line(
                    Line::new(s.name(), PlotPoints::from(points))
                        .color(colour)
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
    };

    panel(
        ui,
        "position_plot",
        main_height,
        &[(Series::Target, p.mnemonic), (Series::Actual, p.written)],
        "position",
        false,
    );
    panel(
        ui,
        "error_plot",
        small_height,
        &[(Series::Error, p.error)],
        "error",
        !show_velocity,
    );
    if show_velocity {
        panel(
            ui,
            "velocity_plot",
            small_height,
            &[(Series::Velocity, p.operation)],
            "counts/s",
            true,
        );
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
        .and_then(|t| readout(trace, t.min(furthest), micros))
        .or_else(|| {
            view.selected_tick
                .and_then(|t| readout(trace, t, micros))
                .map(|r| format!("selected {r}"))
        })
        .unwrap_or_else(|| "Hover the plot to read values; click to go to that tick.".to_string());
    ui.label(RichText::new(text).monospace().small());
}

//! The gutter beside the text: line numbers, breakpoints, the line about to run, the call
//! stack, rung power and addresses.

use super::*;

/// Where each line of the laid-out program text is (one row per line: the text never wraps).
pub(super) struct LineRows {
    /// Top and bottom of each line, in screen coordinates; line n is index n - 1.
    pub(super) spans: Vec<(f32, f32)>,
    pub(super) left: f32,
}

impl LineRows {
    pub(super) fn of(galley: &egui::Galley, origin: egui::Pos2, left: f32) -> Self {
        let spans = galley
            .rows
            .iter()
            .map(|row| {
                let rect = row.rect().translate(origin.to_vec2());
                (rect.top(), rect.bottom())
            })
            .collect();
        LineRows { spans, left }
    }

    /// The row of `line` (1-based), from the text's left edge.
    pub(super) fn rect(&self, line: usize) -> Option<Rect> {
        let &(top, bottom) = self.spans.get(line.checked_sub(1)?)?;
        Some(Rect::from_min_max(
            pos2(self.left, top),
            pos2(self.left + 1.0, bottom),
        ))
    }

    /// The line at height `y`.
    pub(super) fn line_at(&self, y: f32) -> Option<usize> {
        let i = self.spans.partition_point(|&(_, bottom)| bottom <= y);
        (i < self.spans.len() && self.spans[i].0 <= y).then_some(i + 1)
    }

    /// The lines whose rows meet the band `top..bottom`.
    pub(super) fn visible(&self, top: f32, bottom: f32) -> std::ops::Range<usize> {
        let first = self.spans.partition_point(|&(_, b)| b <= top);
        let last = self.spans.partition_point(|&(t, _)| t < bottom);
        first + 1..last + 1
    }
}

/// What the gutter shows of the file in view, at its own line numbers.
pub(super) struct GutterView<'a> {
    /// The program line before the file's first (its lines are `base + 1 ..`).
    pub(super) base: usize,
    pub(super) diagnostics: &'a [Diagnostic],
    pub(super) power: &'a [(usize, servoscope_core::machine::LinePower)],
    /// Program lines and the address of the statement starting each (when shown).
    pub(super) addresses: &'a [(usize, u32)],
}

#[allow(clippy::too_many_arguments)]
pub(super) fn gutter_ui(
    ui: &mut egui::Ui,
    debugger: &Debugger,
    gutter: Rect,
    rows: &LineRows,
    pc_line: Option<usize>,
    gv: &GutterView<'_>,
    p: &Palette,
    font: &FontId,
    out: &mut Vec<Command>,
) {
    let clip = ui.clip_rect();
    // The gutter stays at the view's left edge when a long line scrolls the text sideways,
    // over the text that scrolls under it.
    let shift = (clip.left() - gutter.left()).max(0.0);
    let gutter = gutter.translate(vec2(shift, 0.0));
    if shift > 0.0 {
        ui.painter().rect_filled(
            gutter.with_max_x(gutter.right() + 4.0).intersect(clip),
            0.0,
            ui.visuals().panel_fill,
        );
    }
    let base = gv.base;
    let error_lines: Vec<usize> = gv.diagnostics.iter().map(|d| d.line).collect();
    let warning_only = |line: usize| {
        gv.diagnostics
            .iter()
            .filter(|d| d.line == line)
            .all(|d| d.severity == servoscope_core::machine::Severity::Warning)
    };
    let power = gv.power;
    // Per line: whether any breakpoint is on it, any enabled, and any with more than a line.
    let marks: std::collections::BTreeMap<usize, (bool, bool)> = debugger
        .breakpoint_list()
        .iter()
        .filter_map(|b| {
            let line = b.line_number()?;
            (line > base && line < base + FILE_LINES).then(|| (line - base, b))
        })
        .fold(Default::default(), |mut acc, (line, b)| {
            let entry = acc.entry(line).or_insert((false, false));
            entry.0 |= b.enabled;
            entry.1 |= !b.is_plain() && b.enabled;
            acc
        });
    for line in rows.visible(clip.top(), clip.bottom()) {
        let Some(text_row) = rows.rect(line) else {
            continue;
        };
        let row = Rect::from_min_max(
            pos2(gutter.left(), text_row.top()),
            pos2(gutter.right(), text_row.bottom()),
        );
        let row_height = row.height();
        let id = Id::unique(("gutter", line));
        let response = ui.interact(row, id, Sense::click());
        let label = format!("Breakpoint line {line}");
        let mark = marks.get(&line).copied();
        let has_bp = mark.is_some_and(|(enabled, _)| enabled);
        response
            .widget_info(|| egui::WidgetInfo::selected(egui::Role::CheckBox, true, has_bp, &label));
        if response.clicked() {
            out.push(Command::Debug(Action::ToggleBreakpoint(base + line)));
        }
        let response = response.on_hover_text_at_pointer(
            "Click: breakpoint. Right-click: a conditional breakpoint or a log point",
        );
        response.context_menu(|ui| {
            if ui.button("Add a conditional breakpoint").clicked() {
                out.push(Command::AddBreakpoint(
                    servoscope_core::debugger::Breakpoint::line(base + line).with_condition("1"),
                ));
                ui.close();
            }
            if ui.button("Add a log point").clicked() {
                out.push(Command::AddBreakpoint(
                    servoscope_core::debugger::Breakpoint::line(base + line)
                        .with_log(format!("line {}", debugger.describe_line(base + line))),
                ));
                ui.close();
            }
        });
        let painter = ui.painter();
        let has_error = error_lines.contains(&line);
        if response.hovered() && !has_bp {
            painter.circle_filled(
                row.left_center() + vec2(row_height * 0.5, 0.0),
                row_height * 0.3,
                p.breakpoint.gamma_multiply(0.35),
            );
        }
        match mark {
            // Enabled, with a condition, count or message: a ring around a dot.
            Some((true, true)) => {
                let centre = row.left_center() + vec2(row_height * 0.5, 0.0);
                painter.circle_stroke(centre, row_height * 0.32, Stroke::new(1.5, p.breakpoint));
                painter.circle_filled(centre, row_height * 0.16, p.breakpoint);
            }
            Some((true, false)) => {
                painter.circle_filled(
                    row.left_center() + vec2(row_height * 0.5, 0.0),
                    row_height * 0.32,
                    p.breakpoint,
                );
            }
            // Disabled: an outline.
            Some((false, _)) => {
                painter.circle_stroke(
                    row.left_center() + vec2(row_height * 0.5, 0.0),
                    row_height * 0.3,
                    Stroke::new(1.0, p.breakpoint.gamma_multiply(0.6)),
                );
            }
            None => {}
        }
        if pc_line == Some(line) {
            let tip = row.left_center() + vec2(row_height * 1.45, 0.0);
            let h = row_height * 0.3;
            painter.add(egui::Shape::convex_polygon(
                vec![
                    tip + vec2(-h * 1.3, -h),
                    tip + vec2(0.0, 0.0),
                    tip + vec2(-h * 1.3, h),
                ],
                p.written,
                Stroke::NONE,
            ));
        }
        // Rung power after this line's instruction (ladder dialects): a bar at the gutter's edge.
        if let Some((_, state)) = power.iter().find(|(l, _)| *l == line) {
            let colour = match state {
                servoscope_core::machine::LinePower::On => p.bit_on,
                servoscope_core::machine::LinePower::Off
                | servoscope_core::machine::LinePower::Skipped
                | servoscope_core::machine::LinePower::MasterOff => p.dim,
                servoscope_core::machine::LinePower::NotRun => egui::Color32::TRANSPARENT,
            };
            let bar = Rect::from_min_max(
                pos2(row.right() - 3.0, row.top() + 2.0),
                pos2(row.right() - 1.0, row.bottom() - 2.0),
            );
            painter.rect_filled(bar, 0.0, colour);
        }
        let number_color = match has_error {
            true if warning_only(line) => p.written,
            true => p.error,
            false => p.dim,
        };
        painter.text(
            row.right_center() - vec2(6.0, 0.0),
            egui::Align2::RIGHT_CENTER,
            line.to_string(),
            font.clone(),
            number_color,
        );
        // The address of the line's first statement in program memory.
        if let Ok(k) = gv
            .addresses
            .binary_search_by_key(&(base + line), |&(l, _)| l)
        {
            painter.text(
                pos2(row.left() + row_height * 1.6, row.center().y),
                egui::Align2::LEFT_CENTER,
                format!("{:04X}", gv.addresses[k].1),
                font.clone(),
                p.dim,
            );
        }
        if has_error {
            let messages: Vec<String> = gv
                .diagnostics
                .iter()
                .filter(|d| d.line == line)
                .map(|d| d.message.clone())
                .collect();
            response.on_hover_text(messages.join("\n"));
        }
    }
}

use super::*;

#[test]
fn highlight_keeps_the_text_exactly() {
    let text = "WRP 11, 1\r\n\nbad: BOGUS ; x\nü\n";
    let classify = servoscope_core::machine::silverlode::syntax::classify;
    let job = highlight(text, classify, &palette(true), &FontId::monospace(12.0));
    assert_eq!(job.text, text);
}

/// Issue #22 item 13: an error's underline lies inside its own row, under its own columns,
/// so a line scrolled out of view leaves nothing on the line below it.
#[test]
fn error_underlines_stay_inside_their_row() {
    let text = "WRP 11, 1\n\nbad: BOGUS ; x\nEND\n";
    let diags = vec![Diagnostic::error(3, 6, 5, "unknown")];
    let classify = servoscope_core::machine::silverlode::syntax::classify;
    let ctx = egui::Context::default();
    let mut shapes = Vec::new();
    let mut rows = Vec::new();
    let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
        let job = highlight(text, classify, &palette(true), &FontId::monospace(12.0));
        let galley = ui.fonts_mut(|f| f.layout_job(job));
        let origin = pos2(10.0, 20.0);
        rows = galley
            .rows
            .iter()
            .map(|r| r.rect().translate(origin.to_vec2()))
            .collect();
        shapes = error_underlines(
            &galley,
            origin,
            1,
            &diags,
            1..5,
            egui::Color32::RED,
            egui::Color32::YELLOW,
        );
        assert!(
            error_underlines(
                &galley,
                origin,
                1,
                &diags,
                4..5,
                egui::Color32::RED,
                egui::Color32::YELLOW
            )
            .is_empty()
        );
    });
    output.textures_delta.clear();
    assert_eq!(shapes.len(), 1);
    let bounds = shapes[0].visual_bounding_rect();
    let row = rows[2];
    assert!(
        bounds.top() >= row.top() && bounds.bottom() <= row.bottom(),
        "{bounds:?} leaves row {row:?}"
    );
    let egui::Shape::LineSegment { points, .. } = shapes[0] else {
        panic!("a line");
    };
    let char_width = row.width() / "bad: BOGUS ; x".len() as f32;
    assert!((points[0].x - (row.left() + 5.0 * char_width)).abs() < 0.5);
    assert!((points[1].x - points[0].x - 5.0 * char_width).abs() < 0.5);
}

#[test]
fn lines_and_chars() {
    let text = "a\nbc\nd";
    assert_eq!(line_of_char(text, 0), 1);
    assert_eq!(line_of_char(text, 3), 2);
    assert_eq!(char_of_line(text, 3), 5);
    assert_eq!(char_of_line(text, 1), 0);
}

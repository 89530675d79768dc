//! What a frame asks the renderer to fill. Without a GPU every filled pixel is shaded in
//! software, on the same cores as the simulation: the panels leave their background to the
//! window's clear colour instead of filling it again each frame. And each change of clip
//! rectangle between the shapes of a frame starts another mesh, which the window's thread
//! uploads and draws on its own (a buffer allocation and a draw call each, without a GPU):
//! rows and bit lines draw inside their panel's clip.

use eframe::App as _;
use egui::Rect;
use egui::epaint::{ClippedShape, Primitive, Shape};
use egui_kittest::Harness;
use servoscope::ui::{Command, Prefs, ServoscopeApp};
use servoscope_core::registry;

/// The area of the opaque rectangles a frame fills, less the harness's own background (the
/// frame egui_kittest puts around the app, 8 points in from the window's edge).
fn filled_area(shapes: &[ClippedShape], window: Rect) -> f32 {
    let harness_background = window.shrink(8.0);
    shapes
        .iter()
        .filter_map(|clipped| match &clipped.shape {
            Shape::Rect(rect) if rect.fill.a() > 0 && rect.rect != harness_background => {
                Some(rect.rect.intersect(clipped.clip_rect))
            }
            _ => None,
        })
        .filter(|r| r.is_positive())
        .map(|r| r.area())
        .sum()
}

#[test]
fn the_window_is_cleared_to_the_panels_colour() {
    let app = ServoscopeApp::new(Prefs::default());
    for visuals in [egui::Visuals::dark(), egui::Visuals::light()] {
        let clear = app.clear_color(&visuals);
        assert_eq!(clear, visuals.panel_fill.to_normalized_gamma_f32());
        assert_eq!(clear[3], 1.0, "an opaque background: nothing shows through");
    }
}

#[test]
fn a_frame_mid_run_fills_less_than_a_third_of_the_window_for_every_example() {
    for (w, h) in [(900.0, 600.0), (1280.0, 800.0), (1920.0, 1080.0)] {
        let window = Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(w, h));
        each_example_mid_run(window.size(), |name, harness| {
            let area = filled_area(&harness.output().shapes, window);
            let share = area / window.area();
            assert!(
                share < 0.33,
                "{w}×{h}, {name}: filled rectangles cover {:.0} % of the window",
                share * 100.0
            );
            // The panels are there all the same (the tiles, the menu, the status bar).
            assert!(
                harness.state().layout.pane_rects().len() >= 4,
                "{name}: the layout shows its panes"
            );
        });
    }
}

/// Loads each example in turn and gives its frame mid-run (where the registers, the plot and
/// the explanation all have something) to `check`.
fn each_example_mid_run(
    size: egui::Vec2,
    mut check: impl FnMut(&str, &Harness<'_, ServoscopeApp>),
) {
    let mut harness = Harness::builder().with_size(size).build_ui_state(
        |ui, app: &mut ServoscopeApp| app.show(ui),
        ServoscopeApp::new(Prefs::default()),
    );
    for (i, (_, name, _)) in registry::examples().enumerate() {
        let ctx = harness.ctx.clone();
        harness.state_mut().apply(&ctx, Command::LoadExample(i));
        if harness.state().pending.is_some() {
            harness.state_mut().apply(&ctx, Command::DiscardAndContinue);
        }
        harness.state_mut().debugger.goto_tick(200);
        harness.run_steps(3);
        check(name, &harness);
    }
}

#[test]
fn rows_and_bit_lines_draw_inside_their_panels_clip() {
    let size = egui::vec2(1280.0, 800.0);
    each_example_mid_run(size, |name, harness| {
        let meshes: Vec<_> = harness
            .ctx
            .tessellate(harness.output().shapes.clone(), 1.0)
            .into_iter()
            .filter(|p| matches!(p.primitive, Primitive::Mesh(_)))
            .collect();
        // A clip of its own on a table cell (a register's name) or on a line of bits made a
        // mesh per row: 46 to 67 meshes a frame before, 34 to 43 after (the harness's own
        // background is 3 of them); a PLC program's plot of its lamps adds up to 4 (#43
        // item 12: 47 for the OpenNet traffic light).
        for mesh in &meshes {
            assert!(
                mesh.clip_rect.height() >= 40.0,
                "{name}: a clip rectangle the size of a row, {:?}",
                mesh.clip_rect
            );
        }
        assert!(
            meshes.len() <= 49,
            "{name}: {} meshes to draw a frame",
            meshes.len()
        );
    });
}

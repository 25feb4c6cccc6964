//! The wasm API in a real browser (`./build.sh test` runs it through
//! wasm-bindgen-test-runner and Chromium): a player over two canvases opens
//! the demo, plays, seeks, recomputes, exports, and survives bad input.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![cfg(target_arch = "wasm32")]

use embusen::web::Player;
use wasm_bindgen::JsCast;
use wasm_bindgen_test::*;
use web_sys::HtmlCanvasElement;

wasm_bindgen_test_configure!(run_in_browser);

fn canvas(width: u32, height: u32) -> HtmlCanvasElement {
    let document = web_sys::window().unwrap().document().unwrap();
    let canvas: HtmlCanvasElement = document.create_element("canvas").unwrap().dyn_into().unwrap();
    canvas.set_width(width);
    canvas.set_height(height);
    document.body().unwrap().append_child(&canvas).unwrap();
    canvas
}

fn player() -> Player {
    let mut player = Player::new(canvas(320, 240), canvas(400, 300)).expect("WebGL2 player");
    player.resize(320, 240, 400, 300);
    player.load_demo().expect("demo opens");
    player
}

#[wasm_bindgen_test]
fn demo_opens_and_plays() {
    let mut player = player();
    let demo = embusen::synth::demo::demo();
    assert_eq!(player.frame_count() as usize, demo.true_root_cm.len());
    assert_eq!(player.fps(), 100.0);
    assert_eq!(player.feet(), ["LeftFoot", "RightFoot"]);
    assert_eq!(player.frame(), 0);
    player.set_playing(true);
    player.tick(0.1);
    assert_eq!(player.frame(), 10);
    player.set_speed(2.0);
    player.tick(0.1);
    assert_eq!(player.frame(), 30);
    player.step(-5);
    assert_eq!(player.frame(), 25);
}

#[wasm_bindgen_test]
fn bad_input_keeps_the_open_recording() {
    let mut player = player();
    player.set_frame(42);
    let frames = player.frame_count();
    let text = b"HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n";
    assert!(player.load("broken.bvh", text, None, None).is_err());
    assert_eq!(player.frame_count(), frames);
    assert_eq!(player.frame(), 42);
    assert_eq!(player.name(), embusen::synth::demo::DEMO_NAME);
    assert!(player.set_settings("paper", "clean", 1.0, 5.0, "NoSuchJoint", "", None).is_err());
    assert_eq!(player.feet(), ["LeftFoot", "RightFoot"]);
}

#[wasm_bindgen_test]
fn settings_recompute_and_exports_match_the_core() {
    let mut player = player();
    assert_eq!(player.method(), "contact", "contact is the default");
    let contact = player.export_hips_csv();
    player.set_settings("paper", "faithful", 1.0, 5.0, "", "", None).unwrap();
    let faithful = player.export_hips_csv();
    assert_ne!(contact[1], faithful[1]);
    player.set_settings("paper", "clean", 0.5, 3.0, "", "", None).unwrap();
    let clean = player.export_hips_csv();
    assert_eq!(clean[0], "recording.hips.csv");
    assert_ne!(faithful[1], clean[1]);
    // The exported BVH is what the core writes for the same settings.
    let recording = embusen::synth::demo::demo().recording();
    let mut settings = embusen::app::session::Settings { use_paper: true, ..Default::default() };
    settings.paper.smoothing = embusen::translate::paper::Smoothing::Clean;
    settings.paper.window_s = 0.5;
    settings.paper.dy_eps_cm = 3.0;
    let session = embusen::app::session::Session::open(recording, settings).unwrap();
    assert_eq!(player.export_recording()[1], session.export_recording().1);
}

#[wasm_bindgen_test]
fn clicking_a_plot_seeks() {
    let mut player = player();
    player.draw();
    // Somewhere in the middle of the plots' left column there is a time panel.
    let mut moved = false;
    for y in (20..300).step_by(20) {
        if player.seek_plot(200.0, y as f32) && player.frame() > 0 {
            moved = true;
            break;
        }
    }
    assert!(moved, "no plot position seeks");
    assert!(!player.seek_plot(-10.0, -10.0));
}

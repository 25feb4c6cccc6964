//! The wasm API in a real browser (`./build.sh test` runs it through
//! wasm-bindgen-test-runner and Chromium): a player over two canvases opens
//! the demo, plays, seeks, recomputes, exports, and survives bad input; the
//! settings and results cross as typed objects, an unknown value an error.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![cfg(target_arch = "wasm32")]

use embusen::translate::MethodKind;
use embusen::translate::hachaj::Smoothing;
use embusen::web::Player;
use embusen::web::api::{self, Ghost};
use tsify::{Ts, Tsify};
use wasm_bindgen::{JsCast, JsValue};
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

/// The settings in use with `change` applied.
fn settings(player: &Player, change: impl FnOnce(&mut api::PlayerSettings)) -> Ts<api::PlayerSettings> {
    let mut settings = player.settings().unwrap().to_rust().unwrap();
    change(&mut settings);
    settings.into_ts().unwrap()
}

/// A JavaScript value as the page might send it, from JSON.
fn js(json: &str) -> JsValue {
    js_sys::JSON::parse(json).unwrap()
}

fn error_message(e: wasm_bindgen::JsError) -> String {
    let value: JsValue = e.into();
    js_sys::Reflect::get(&value, &"message".into()).unwrap().as_string().unwrap()
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
    let info = player.info().unwrap().to_rust().unwrap();
    assert_eq!((info.feet.left.as_str(), info.feet.right.as_str()), ("LeftFoot", "RightFoot"));
    assert_eq!(info.frame_count, demo.true_root_cm.len());
    assert_eq!(player.frame(), 0);
    player.set_playing(true);
    player.tick(0.1);
    assert_eq!(player.frame(), 10);
    player.set_speed(2.0).unwrap();
    assert!(player.set_speed(f64::NAN).is_err());
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
    assert_eq!(player.info().unwrap().to_rust().unwrap().name, embusen::synth::demo::DEMO_NAME);
    let before = player.settings().unwrap().to_rust().unwrap();
    let bad = settings(&player, |s| {
        s.method = MethodKind::Hachaj;
        s.left_foot = Some("NoSuchJoint".to_string());
    });
    assert!(player.set_settings(bad).is_err());
    assert_eq!(player.settings().unwrap().to_rust().unwrap(), before, "nothing changed");
    assert_eq!(player.info().unwrap().to_rust().unwrap().feet.left, "LeftFoot");
}

#[wasm_bindgen_test]
fn unknown_values_and_fields_are_errors_that_name_them() {
    let mut player = player();
    let good = r#"{"method":"paper","smoothing":"clean","window_s":1,"dy_eps_cm":5,"sole_depth_cm":null,"left_foot":null,"right_foot":null}"#;
    player.set_settings(Ts::new_unchecked(js(good))).unwrap();
    assert_eq!(player.settings().unwrap().to_rust().unwrap().method, MethodKind::Hachaj);
    let cases = [
        (good.replace("\"paper\"", "\"papier\""), "papier"),
        (good.replace("\"clean\"", "\"smooth\""), "smooth"),
        (good.replace("\"window_s\"", "\"window\""), "window"),
        (good.replace("}", r#","alpha":2}"#), "alpha"),
        (good.replace("\"dy_eps_cm\":5", "\"dy_eps_cm\":500"), "500"),
        (good.replace("\"sole_depth_cm\":null", "\"sole_depth_cm\":-1"), "-1"),
    ];
    for (json, named) in cases {
        let Err(e) = player.set_settings(Ts::new_unchecked(js(&json))) else { panic!("{json} was taken") };
        let message = error_message(e);
        assert!(message.contains(named), "{json}: {message}");
    }
    assert_eq!(player.settings().unwrap().to_rust().unwrap().smoothing, Smoothing::Clean, "unchanged");
    player.set_ghost(Ghost::Side.into_ts().unwrap()).unwrap();
    let message = error_message(player.set_ghost(Ts::new_unchecked("sideways".into())).unwrap_err());
    assert!(message.contains("sideways"), "{message}");
}

#[wasm_bindgen_test]
fn the_options_defaults_are_the_players() {
    let options = embusen::web::options().unwrap().to_rust().unwrap();
    let player = player();
    let defaults = &options.defaults;
    assert_eq!(player.settings().unwrap().to_rust().unwrap(), defaults.settings);
    assert_eq!(defaults.settings.method, MethodKind::Contact);
    assert_eq!((defaults.settings.window_s, defaults.settings.dy_eps_cm), (1.0, 5.0), "RMoCap's");
    assert_eq!(defaults.settings.sole_depth_cm, None, "estimated");
    assert_eq!(options.sole_depths_cm, embusen::translate::contact::SOLE_DEPTHS_CM);
    assert!(options.speeds.contains(&defaults.speed));
    assert!(options.methods.iter().any(|m| m.value == MethodKind::Hachaj));
    assert_eq!(defaults.ghost, Ghost::Overlay);
    // Every offered choice is accepted.
    let mut player = player;
    for depth in options.sole_depths_cm.iter().map(|&d| Some(d)).chain([None]) {
        player.set_settings(settings(&player, |s| s.sole_depth_cm = depth)).unwrap();
    }
    for ghost in &options.ghosts {
        player.set_ghost(ghost.value.into_ts().unwrap()).unwrap();
    }
}

#[wasm_bindgen_test]
fn settings_recompute_and_exports_match_the_core() {
    let mut player = player();
    assert_eq!(
        player.info().unwrap().to_rust().unwrap().method,
        MethodKind::Contact,
        "contact is the default"
    );
    let sole = player.info().unwrap().to_rust().unwrap().sole_depth.unwrap();
    assert!(sole.estimated);
    let hips = |player: &Player| player.export_hips_csv().unwrap().to_rust().unwrap();
    let contact = hips(&player);
    player.set_settings(settings(&player, |s| s.method = MethodKind::Hachaj)).unwrap();
    assert_eq!(player.info().unwrap().to_rust().unwrap().sole_depth, None, "the paper method has no sole");
    let faithful = hips(&player);
    assert_ne!(contact.text, faithful.text);
    player
        .set_settings(settings(&player, |s| {
            s.smoothing = Smoothing::Clean;
            s.window_s = 0.5;
            s.dy_eps_cm = 3.0;
        }))
        .unwrap();
    let clean = hips(&player);
    assert_eq!(clean.name, "recording.hips.csv");
    assert_ne!(faithful.text, clean.text);
    // The exported BVH is what the core writes for the same settings.
    let recording = embusen::synth::demo::demo().recording();
    let mut settings = embusen::app::session::Settings { method: MethodKind::Hachaj, ..Default::default() };
    settings.hachaj.smoothing = Smoothing::Clean;
    settings.hachaj.window_s = 0.5;
    settings.hachaj.dy_eps_cm = 3.0;
    let session = embusen::app::session::Session::open(recording, settings).unwrap();
    assert_eq!(player.export_recording().unwrap().to_rust().unwrap().text, session.export_recording().1);
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

#[wasm_bindgen_test]
fn a_panic_report_reaches_the_page() {
    use std::cell::RefCell;
    use std::rc::Rc;
    use wasm_bindgen::closure::Closure;
    let got = Rc::new(RefCell::new(None));
    let sink = got.clone();
    let listener = Closure::<dyn FnMut(web_sys::CustomEvent)>::new(move |e: web_sys::CustomEvent| {
        *sink.borrow_mut() = e.detail().as_string();
    });
    let window = web_sys::window().unwrap();
    window
        .add_event_listener_with_callback(embusen::web::PANIC_EVENT, listener.as_ref().unchecked_ref())
        .unwrap();
    embusen::web::report_panic("panicked at here: on purpose");
    window
        .remove_event_listener_with_callback(embusen::web::PANIC_EVENT, listener.as_ref().unchecked_ref())
        .unwrap();
    assert_eq!(got.borrow().as_deref(), Some("panicked at here: on purpose"));
}

#[wasm_bindgen_test]
fn without_a_recording_results_are_errors() {
    let player = Player::new(canvas(32, 32), canvas(32, 32)).unwrap();
    assert_eq!(player.frame_count(), 0);
    assert!(player.info().is_err());
    assert!(player.export_recording().is_err());
    assert!(player.settings().is_err());
}

/// The camera panel's plots and the path scorer read their objects as the
/// rest of the boundary does: an unknown field refused at any depth, named
/// where it is (a list's item by its index), what is known still taken.
#[wasm_bindgen_test]
fn the_plots_and_the_path_work_refuse_unknown_fields_at_any_depth() {
    use embusen::web::camera_api::PathWork;
    use embusen::web::camera_plots::{paint_candidates, paint_top_view};
    let plot = canvas(64, 48);
    let candidates = |floor: &str| {
        format!(
            r#"{{"tried": [{{"floor": {{"x_cm": 1, "z_cm": 2}}, "energy_px": 3}}, {{"floor": {floor}, "energy_px": 4}}], "chosen": 0}}"#
        )
    };
    let paint = |json: String| paint_candidates(&plot, Some(Ts::new_unchecked(js(&json))), 0);
    paint(candidates(r#"{"x_cm": 5, "z_cm": 6}"#)).unwrap();
    let message = error_message(paint(candidates(r#"{"x_cm": 5, "y_cm": 6}"#)).unwrap_err());
    assert!(message.contains("the candidates' tried[1].floor: unknown field `y_cm`"), "{message}");
    let message = error_message(paint(candidates("{}").replace("\"chosen\"", "\"picked\"")).unwrap_err());
    assert!(message.contains("the candidates: unknown field `picked`"), "{message}");
    let point = |json: &str| Ts::new_unchecked(js(json));
    paint_top_view(&plot, vec![point(r#"{"x_cm": 1, "z_cm": 2}"#)]).unwrap();
    let message =
        error_message(paint_top_view(&plot, vec![point(r#"{"x_cm": 1, "z_cm": 2, "w": 0}"#)]).unwrap_err());
    assert!(message.contains("unknown field `w`"), "{message}");
    let work = |candidate: &str| {
        let json = format!(
            r#"{{"frame": 0, "terms_at": {{"x_cm": 0, "z_cm": 0}}, "truncate_px": null, "working_scale_quarters": 4, "candidates": [{{"x_cm": 1, "z_cm": 2}}, {candidate}]}}"#
        );
        PathWork::from_js(Ts::new_unchecked(js(&json)))
    };
    assert_eq!(work(r#"{"x_cm": 3, "z_cm": 4}"#).unwrap().candidates_cm.len(), 2);
    let message = work(r#"{"x_cm": 3, "z": 4}"#).unwrap_err();
    assert!(message.contains("the path request's candidates[1]: unknown field `z`"), "{message}");
}

/// The camera module's boundary refuses what it does not know: an unknown
/// field (at any depth), an unknown method, a bad corner count, each named.
#[wasm_bindgen_test]
fn the_camera_boundary_refuses_unknown_fields_and_values() {
    use embusen::web::camera_view::calibrate_floor_corners;
    use embusen::web::tracking::{CameraJob, FinishedTakeView};
    let corners = r#"{"width_px": 640, "height_px": 480, "corners": [{"x_px": 1, "y_px": 2}], "width_cm": 200,
        "depth_cm": 150, "focal_px": null"#;
    let refused =
        |json: String| error_message(calibrate_floor_corners(Ts::new_unchecked(js(&json))).unwrap_err());
    assert!(refused(format!("{corners}, \"focal\": 3}}")).contains("unknown field `focal`"));
    assert!(refused(format!("{corners}}}")).contains("four corners, not 1"));
    let file = r#"{"name": "a", "bytes": []}"#;
    let take = |video: &str, method: &str| {
        format!(
            r#"{{"recording": {file}, "camera": {file}, "background": {file}, "video": {video}, "method": "{method}", "offset_s": 0}}"#
        )
    };
    let video = r#"{"name": "v.mp4", "width_px": 2, "height_px": 2, "fps": 30, "frame_count": 1}"#;
    // Bytes cross as a Uint8Array (JSON has none: put in after parsing).
    let with_bytes = |json: String, files: [&str; 3]| {
        let options = js(&json);
        for file in files {
            let file = js_sys::Reflect::get(&options, &file.into()).unwrap();
            js_sys::Reflect::set(&file, &"bytes".into(), &js_sys::Uint8Array::new_with_length(0)).unwrap();
        }
        options
    };
    let open = |json: String| {
        let options = with_bytes(json, ["recording", "camera", "background"]);
        CameraJob::new(Ts::new_unchecked(options)).err().map(error_message).unwrap_or_default()
    };
    assert!(
        open(take(video, "fused").replace("\"offset_s\"", "\"offset\"")).contains("unknown field `offset`")
    );
    assert!(open(take(video, "kalman")).contains("kalman"), "{}", open(take(video, "kalman")));
    let typo = video.replace("\"fps\"", "\"fsp\"");
    assert!(
        open(take(&typo, "fused")).contains("the take's video: unknown field `fsp`"),
        "{}",
        open(take(&typo, "fused"))
    );
    // A take tracked before, to be shown as it is: the same refusals.
    let finished = |json: String| {
        let options = with_bytes(json, ["recording", "camera", "track"]);
        FinishedTakeView::new(Ts::new_unchecked(options)).err().map(error_message).unwrap_or_default()
    };
    let shown = |video: &str, extra: &str| {
        format!(
            r#"{{"recording": {file}, "camera": {file}, "track": {file}, "video": {video}, "offset_s": 0{extra}}}"#
        )
    };
    assert!(finished(shown(video, ", \"method\": \"fused\"")).contains("unknown field `method`"));
    assert!(finished(shown(&typo, "")).contains("the take's video: unknown field `fsp`"));
    let said = finished(shown(&video.replace("\"fps\": 30", "\"fps\": 0"), ""));
    assert!(said.contains("v.mp4: 1 frames at 0 fps: not a video"), "{said}");
}

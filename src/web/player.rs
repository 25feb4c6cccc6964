//! The recording player: a `Player` that JavaScript creates over two
//! canvases (the 3D view and the plots) and drives from its animation loop.

use std::sync::Arc;

use tsify::{Ts, Tsify};
use wasm_bindgen::prelude::*;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement, WebGl2RenderingContext};

use crate::app::clock::Clock;
use crate::app::plot::{self, CameraSeries, Layout, Stance, TextMeasure};
use crate::app::session::{Session, Settings};
use crate::io::recording::{FeetChoice, Recording};
use crate::io::table::Accelerations;
use crate::track::take::body_shape_of;
use crate::web::api::{Export, FootNames, Ghost, Info, Options, PlotPanel, SoleDepth};
use crate::web::js_object::read_ts;
use crate::web::scene::{CameraTake, Scene};
use crate::web::take_series::TakeSeries;
use crate::web::{api, canvas2d};

/// Every choice the page offers, and the defaults.
#[wasm_bindgen]
pub fn options() -> Result<Ts<Options>, JsError> {
    Ok(Options::new().into_ts()?)
}

fn js_error(e: impl std::fmt::Display) -> JsError {
    JsError::new(&e.to_string())
}

/// One player: a 3D view, a plot canvas, and the recording they show.
#[wasm_bindgen]
pub struct Player {
    view: HtmlCanvasElement,
    plots: HtmlCanvasElement,
    plots_2d: CanvasRenderingContext2d,
    /// The plots without the cursor, painted once per recording, settings or
    /// size and copied under the cursor every frame.
    plots_static: HtmlCanvasElement,
    layout: Layout,
    scene: Scene,
    session: Option<Session>,
    clock: Clock,
    drawn_frame: Option<usize>,
    /// The scene or plots must be rebuilt for the current frame.
    scene_dirty: bool,
    /// Only the camera moved: render again, nothing to rebuild. Without these
    /// flags a paused player would keep the GPU busy every animation frame.
    camera_moved: bool,
}

fn context_2d(canvas: &HtmlCanvasElement) -> Result<CanvasRenderingContext2d, JsError> {
    canvas
        .get_context("2d")
        .map_err(|_| js_error("the plot canvas refused a 2D context"))?
        .ok_or_else(|| js_error("the plot canvas has no 2D context"))?
        .dyn_into::<CanvasRenderingContext2d>()
        .map_err(|_| js_error("the plot canvas gave an unexpected context"))
}

#[wasm_bindgen]
impl Player {
    /// Creates a player over the 3D canvas `view` and the 2D canvas `plots`.
    #[wasm_bindgen(constructor)]
    pub fn new(view: HtmlCanvasElement, plots: HtmlCanvasElement) -> Result<Player, JsError> {
        // `preserveDrawingBuffer` lets tests and screenshots read the pixels.
        let options = js_sys::Object::new();
        for (key, value) in [("preserveDrawingBuffer", true), ("antialias", false)] {
            js_sys::Reflect::set(&options, &key.into(), &value.into())
                .map_err(|_| js_error("cannot set WebGL options"))?;
        }
        let gl = view
            .get_context_with_context_options("webgl2", &options)
            .map_err(|_| js_error("this browser refused a WebGL2 context"))?
            .ok_or_else(|| js_error("this browser has no WebGL2"))?
            .dyn_into::<WebGl2RenderingContext>()
            .map_err(|_| js_error("unexpected WebGL context"))?;
        let glow = three_d::context::Context::from_webgl2_context(gl);
        // three-d wants an Arc; wasm is single-threaded, so it is never shared across threads.
        #[allow(clippy::arc_with_non_send_sync)]
        let context = three_d::Context::from_gl_context(Arc::new(glow)).map_err(js_error)?;
        let document = web_sys::window().and_then(|w| w.document()).ok_or_else(|| js_error("no document"))?;
        let plots_static = document
            .create_element("canvas")
            .map_err(|_| js_error("cannot create a canvas"))?
            .dyn_into::<HtmlCanvasElement>()
            .map_err(|_| js_error("cannot create a canvas"))?;
        let mut scene = Scene::new(context);
        scene.follow = api::FOLLOW_DEFAULT;
        scene.set_solid(api::SOLID_DEFAULT);
        scene.set_shadow(api::SHADOW_DEFAULT);
        scene.ghost = Ghost::default();
        Ok(Player {
            plots_2d: context_2d(&plots)?,
            view,
            plots,
            plots_static,
            layout: plot::layout(1.0, 1.0, TextMeasure::Estimate),
            scene,
            session: None,
            clock: Clock::default(),
            drawn_frame: None,
            scene_dirty: true,
            camera_moved: false,
        })
    }

    /// Opens the built-in demo recording.
    pub fn load_demo(&mut self) -> Result<(), JsError> {
        let recording = crate::synth::demo::demo().recording();
        self.open(recording)
    }

    /// Opens a recording from its bytes (BVH or RMoCap table, told by the
    /// content), with an optional accelerometer side file. On error the
    /// current recording stays open and the error says file:line:column.
    pub fn load(
        &mut self,
        name: &str,
        bytes: &[u8],
        accel_name: Option<String>,
        accel_bytes: Option<Vec<u8>>,
    ) -> Result<(), JsError> {
        let mut recording = Recording::parse(bytes, name, None).map_err(js_error)?;
        match (accel_name, accel_bytes) {
            (Some(accel_name), Some(accel_bytes)) => {
                let accel = Accelerations::parse(&accel_bytes, &accel_name).map_err(js_error)?;
                recording.attach_accel(accel).map_err(js_error)?;
            }
            (None, None) => {}
            (Some(accel_name), None) => {
                return Err(js_error(format!("{accel_name}: the accelerometer file came without its bytes")));
            }
            (None, Some(_)) => return Err(js_error("an accelerometer file came without its name")),
        }
        self.open(recording)
    }

    fn open(&mut self, recording: Recording) -> Result<(), JsError> {
        let settings = match &self.session {
            // Keep the method settings, but not foot names that belong to another skeleton.
            Some(s) => Settings { feet: FeetChoice::default(), ..s.settings.clone() },
            None => Settings::default(),
        };
        let session = Session::open(recording, settings).map_err(js_error)?;
        self.clock.set_recording(session.recording.frame_count(), session.recording.fps);
        // The body model `embusen track` builds for it, read once per
        // recording; none for a skeleton it cannot read a body from
        // (drawn as sticks).
        self.scene.shape = body_shape_of(&session.recording).ok();
        self.session = Some(session);
        // A take belongs to the recording it was tracked from.
        self.scene.set_take(None);
        self.after_change();
        Ok(())
    }

    /// Shows a camera-tracked take of the open recording in the 3D view,
    /// until [`Player::clear_camera_take`] or another recording: in place of
    /// the corrected stick figure, the body model the take was tracked with
    /// (`track::take::body_shape_of` the recording) solid, in frame `f` the
    /// recording's pose of `f` moved so that its hips are at `camera_hips_cm`
    /// of `f` (x, y, z per frame, the recording's own coordinates, cm; a
    /// frame with a non-finite one shows no body); the camera as
    /// `frustum_cm`, line segments of six numbers each (two ends, x, y, z, in
    /// the recording's coordinates, cm); and the camera track's floor path
    /// beside the suit's and the inertial estimate's, in the 3D view and in
    /// the plots' (d); with `series`, per video frame the uncertainty the
    /// tracker states and its error against a truth in the plots' (f). The
    /// view frames the track with the other paths; the floor reaches under
    /// the camera too. On error (no recording open, a length that does not
    /// fit, an unknown field) nothing shown changes.
    pub fn show_camera_take(
        &mut self,
        camera_hips_cm: &[f64],
        frustum_cm: &[f64],
        series: Option<Ts<TakeSeries>>,
    ) -> Result<(), JsError> {
        let session = self.open_session()?;
        let frames = session.recording.frame_count();
        if camera_hips_cm.len() != 3 * frames {
            return Err(js_error(format!(
                "the camera track has {} numbers for a recording of {frames} frames: expected x, y, z per frame, {}",
                camera_hips_cm.len(),
                3 * frames
            )));
        }
        if !frustum_cm.len().is_multiple_of(6) {
            return Err(js_error(format!(
                "the camera frustum has {} numbers: expected 6 per line (two ends, x, y, z each)",
                frustum_cm.len()
            )));
        }
        // The view draws the recording's body model at the track: without
        // one, the error says why the skeleton gives none.
        if self.scene.shape.is_none() {
            body_shape_of(&session.recording).map_err(js_error)?;
        }
        let point = |p: &[f64]| glam::DVec3::new(p[0], p[1], p[2]);
        let hips_cm: Vec<glam::DVec3> = camera_hips_cm.chunks_exact(3).map(point).collect();
        let series: TakeSeries = match series {
            Some(series) => read_ts(&series, "the camera take's series").map_err(js_error)?,
            None => TakeSeries::default(),
        };
        self.open_session_mut()?.set_camera_take(series.with_path(hips_cm.clone())).map_err(js_error)?;
        let take = CameraTake {
            hips_cm,
            frustum_cm: frustum_cm.chunks_exact(6).map(|l| [point(&l[..3]), point(&l[3..])]).collect(),
        };
        self.scene.set_take(Some(take));
        self.after_change();
        Ok(())
    }

    /// What the plots' (f) shows of the camera take, per video frame; none
    /// without a take.
    pub fn camera_take_series(&self) -> Result<Option<Ts<TakeSeries>>, JsError> {
        let camera = &self.open_session()?.plot_data.camera;
        if !camera.is_shown() {
            return Ok(None);
        }
        Ok(Some(TakeSeries::of(camera.clone()).into_ts()?))
    }

    /// Where the plots' (d) draws the camera take's path at frame `frame`:
    /// `[x, y]` in the plot canvas's pixels, for clicks (tests); none
    /// without a take.
    pub fn camera_path_px(&self, frame: usize) -> Result<Option<Vec<f32>>, JsError> {
        let data = &self.open_session()?.plot_data;
        Ok(plot::camera_path_px(data, &self.layout, frame).map(|(x, y)| vec![x, y]))
    }

    /// Back to the recording alone.
    pub fn clear_camera_take(&mut self) {
        if self.scene.has_take() {
            self.scene.set_take(None);
            if let Some(session) = &mut self.session {
                // No take always fits.
                let _ = session.set_camera_take(CameraSeries::default());
            }
            self.after_change();
        }
    }

    /// The scene's trails, floor and framing made again for the session and
    /// the take, and the frame drawn anew.
    fn restage(&mut self) {
        if let Some(s) = &self.session {
            let up_is_z = s.recording.up_axis_is_z();
            self.scene.set_recording(&s.recording.poses, &s.translated.poses, s.translated.hips, up_is_z);
        }
        self.drawn_frame = None;
        self.scene_dirty = true;
    }

    /// After a new recording, new settings or a camera take: the scene's
    /// trails and framing, and the plots' layout and static part, follow
    /// the session.
    fn after_change(&mut self) {
        self.relayout();
        self.restage();
        self.repaint_all();
    }

    /// Everything is drawn again on the next tick, static plots included.
    fn repaint_all(&mut self) {
        self.drawn_frame = None;
        self.scene_dirty = true;
        self.repaint_static_plots();
    }

    /// The method settings in use.
    pub fn settings(&self) -> Result<Ts<api::PlayerSettings>, JsError> {
        let session = self.open_session()?;
        Ok(api::PlayerSettings::from_session(&session.settings).into_ts()?)
    }

    /// Changes the method settings and recomputes; on error (an unknown
    /// value or field, a value out of range, a foot that is no joint)
    /// nothing changes.
    pub fn set_settings(&mut self, settings: Ts<api::PlayerSettings>) -> Result<(), JsError> {
        let settings = api::PlayerSettings::from_js(settings).map_err(js_error)?;
        let Some(session) = &mut self.session else { return Err(js_error("no recording is open")) };
        let settings = settings.apply_to(&session.settings).map_err(js_error)?;
        session.set_settings(settings).map_err(js_error)?;
        self.after_change();
        Ok(())
    }

    fn open_session(&self) -> Result<&Session, JsError> {
        self.session.as_ref().ok_or_else(|| js_error("no recording is open"))
    }

    fn open_session_mut(&mut self) -> Result<&mut Session, JsError> {
        self.session.as_mut().ok_or_else(|| js_error("no recording is open"))
    }

    /// Sets the canvas sizes in device pixels (call on resize).
    pub fn resize(&mut self, view_width: u32, view_height: u32, plots_width: u32, plots_height: u32) {
        self.view.set_width(view_width.max(1));
        self.view.set_height(view_height.max(1));
        self.plots.set_width(plots_width.max(1));
        self.plots.set_height(plots_height.max(1));
        self.plots_static.set_width(plots_width.max(1));
        self.plots_static.set_height(plots_height.max(1));
        self.relayout();
        self.repaint_all();
    }

    /// The plots laid out again for their canvas and what the session shows
    /// (a camera take adds (f)).
    fn relayout(&mut self) {
        let (w, h) = (self.plots.width() as f32, self.plots.height() as f32);
        let text = canvas2d::measure_text(&self.plots_2d);
        self.layout = match &self.session {
            Some(s) => plot::layout_for(&s.plot_data, w, h, TextMeasure::With(&text)),
            None => plot::layout(w, h, TextMeasure::With(&text)),
        };
    }

    fn repaint_static_plots(&mut self) {
        let Some(session) = &self.session else { return };
        let Ok(ctx) = context_2d(&self.plots_static) else { return };
        ctx.clear_rect(0.0, 0.0, self.plots_static.width() as f64, self.plots_static.height() as f64);
        let text = canvas2d::measure_text(&ctx);
        canvas2d::paint(&ctx, &plot::draw_static(&session.plot_data, &self.layout, TextMeasure::With(&text)));
    }

    /// Advances playback by `dt_s` seconds of wall time (when playing) and
    /// draws whatever changed. Call once per animation frame.
    pub fn tick(&mut self, dt_s: f64) {
        self.clock.tick(dt_s);
        if self.scene_dirty || self.camera_moved || self.drawn_frame != Some(self.frame() as usize) {
            self.draw();
        }
    }

    /// Draws the current frame now (3D view and plots).
    pub fn draw(&mut self) {
        let Some(session) = &self.session else { return };
        let frame = self.frame() as usize;
        if self.drawn_frame != Some(frame) || self.scene_dirty {
            let pinned = match session.plot_data.stance.get(frame) {
                Some(Stance::Pinned(foot, _)) => Some((session.translated.feet[*foot], *foot)),
                _ => None,
            };
            self.scene.set_frame(
                &session.recording.poses,
                &session.translated.poses,
                &session.recording.parents,
                frame,
                pinned,
            );
            // Plots: the cached static part, then the cursor.
            let (w, h) = (self.plots.width() as f64, self.plots.height() as f64);
            self.plots_2d.clear_rect(0.0, 0.0, w, h);
            let _ = self.plots_2d.draw_image_with_html_canvas_element(&self.plots_static, 0.0, 0.0);
            let text = canvas2d::measure_text(&self.plots_2d);
            let cursor = plot::draw_cursor(&session.plot_data, frame, &self.layout, TextMeasure::With(&text));
            canvas2d::paint(&self.plots_2d, &cursor);
            self.drawn_frame = Some(frame);
        }
        // The camera may have moved even when the frame did not.
        self.scene.render(self.view.width(), self.view.height());
        self.scene_dirty = false;
        self.camera_moved = false;
    }

    // --- playback -------------------------------------------------------

    /// The current frame index.
    pub fn frame(&self) -> u32 {
        self.clock.frame() as u32
    }

    /// Jumps to `frame`, clamped to the recording.
    pub fn set_frame(&mut self, frame: u32) {
        self.clock.set_frame(frame as usize);
    }

    /// Moves by `frames` (negative: back), clamped to the recording.
    pub fn step(&mut self, frames: i32) {
        self.clock.step(i64::from(frames));
    }

    pub fn frame_count(&self) -> u32 {
        self.clock.frame_count() as u32
    }

    pub fn fps(&self) -> f64 {
        self.clock.fps()
    }

    /// The time of the current frame (s).
    pub fn time_s(&self) -> f64 {
        self.clock.frame_time_s()
    }

    pub fn playing(&self) -> bool {
        self.clock.playing()
    }

    pub fn set_playing(&mut self, playing: bool) {
        self.clock.set_playing(playing);
    }

    /// Playback speed, clamped to 0.25–4×; not a number is an error.
    pub fn set_speed(&mut self, speed: f64) -> Result<(), JsError> {
        if speed.is_nan() {
            return Err(js_error("the playback speed must be a number, not NaN"));
        }
        self.clock.set_speed(speed);
        Ok(())
    }

    pub fn set_looping(&mut self, looping: bool) {
        self.clock.set_looping(looping);
    }

    // --- view -----------------------------------------------------------

    pub fn orbit(&mut self, dx_px: f32, dy_px: f32) {
        self.scene.orbit(dx_px, dy_px);
        self.camera_moved = true;
    }

    pub fn pan(&mut self, dx_px: f32, dy_px: f32) {
        self.scene.pan(dx_px, dy_px);
        self.camera_moved = true;
    }

    /// Zooms by `factor` (< 1 closer, > 1 farther).
    pub fn zoom(&mut self, factor: f32) {
        self.scene.zoom(factor);
        self.camera_moved = true;
    }

    pub fn set_follow(&mut self, follow: bool) {
        self.scene.follow = follow;
        self.scene_dirty = true;
    }

    /// Lets the body (every recording's, a camera take's) cast its soft
    /// shadow on the floor, or not.
    pub fn set_shadow(&mut self, shadow: bool) {
        self.scene.set_shadow(shadow);
        self.scene_dirty = true;
    }

    /// Draws the body solid (the body model scaled to the skeleton, where
    /// one can be read from it), or as a stick figure. A camera take's body
    /// is always solid: it is the model the camera matched.
    pub fn set_solid(&mut self, solid: bool) {
        self.scene.set_solid(solid);
        self.drawn_frame = None;
        self.scene_dirty = true;
    }

    /// How the original skeleton is shown; an unknown mode is an error.
    pub fn set_ghost(&mut self, mode: Ts<Ghost>) -> Result<(), JsError> {
        self.scene.ghost = read_ts(&mode, "the ghost mode").map_err(js_error)?;
        self.scene_dirty = true;
        Ok(())
    }

    /// A click or drag on the plots at (x, y) canvas pixels: seeks to the
    /// frame under it and returns true, or returns false outside the plots.
    pub fn seek_plot(&mut self, x: f32, y: f32) -> bool {
        let Some(session) = &self.session else { return false };
        match plot::frame_at(&session.plot_data, &self.layout, x, y) {
            Some(frame) => {
                self.set_frame(frame as u32);
                true
            }
            None => false,
        }
    }

    // --- information and export -----------------------------------------

    /// What the info panel shows about the open recording and its result.
    pub fn info(&self) -> Result<Ts<Info>, JsError> {
        let s = self.open_session()?;
        let names = &s.recording.joint_names;
        let sole_depth = s
            .translated
            .contact()
            .and_then(|c| c.sole_depth_cm)
            .map(|depth_cm| SoleDepth { depth_cm, estimated: s.settings.contact.sole_depth_cm.is_none() });
        let info = Info {
            name: s.recording.name.clone(),
            joint_names: names.clone(),
            frame_count: s.recording.frame_count(),
            fps: s.recording.fps,
            duration_s: s.recording.duration_s(),
            feet: FootNames {
                left: names[s.translated.feet.left].clone(),
                right: names[s.translated.feet.right].clone(),
            },
            method: s.settings.method,
            sole_depth,
            accel_source: s.translated.accel_source.to_string(),
            warnings: s.recording.warnings.iter().chain(s.translated.decisions.warnings()).cloned().collect(),
        };
        Ok(info.into_ts()?)
    }

    /// The plot panels in pixels of the plot canvas, in the order of
    /// `plot::Panel`; tests click into them.
    pub fn plot_panels(&self) -> Result<Vec<Ts<PlotPanel>>, JsError> {
        let rects = self.layout.plot_rects_xywh();
        let panels = rects.chunks_exact(4).map(|r| PlotPanel { x: r[0], y: r[1], width: r[2], height: r[3] });
        Ok(panels.map(|p| p.into_ts()).collect::<Result<_, _>>()?)
    }

    /// The corrected recording (BVH or table).
    pub fn export_recording(&self) -> Result<Ts<Export>, JsError> {
        let (name, text) = self.open_session()?.export_recording();
        Ok(Export { name, text }.into_ts()?)
    }

    /// The hips trajectory CSV.
    pub fn export_hips_csv(&self) -> Result<Ts<Export>, JsError> {
        let (name, text) = self.open_session()?.export_hips_csv();
        Ok(Export { name, text }.into_ts()?)
    }
}

/// Parses a BVH and computes the global position of every joint in every
/// frame, returning the frame count: the work the benchmark compares with
/// three.js's `BVHLoader`.
#[wasm_bindgen]
pub fn parse_and_kinematics(bytes: &[u8]) -> Result<u32, JsError> {
    let bvh = crate::io::bvh::Bvh::parse(bytes, "bench.bvh", &crate::io::bvh::ReadOptions::default())
        .map_err(js_error)?;
    let poses = crate::body::kinematics::forward_kinematics(&bvh.skeleton, &bvh.motion);
    Ok(poses.frame_count() as u32)
}

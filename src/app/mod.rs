//! What the app shows, still browser-free so native tests drive it: the open
//! [`session::Session`] (a recording, its settings and result), a camera
//! [`tracking::TrackingJob`] fed the video's frames one by one (what it
//! reports of each, [`frame_report`]), a take
//! tracked before opened to be watched ([`finished_take`]), the plots laid
//! out as shapes, the pipeline's stages of a frame painted over the video
//! ([`frame_layers`]), and the one colour theme of the plots and the 3D view. May
//! import everything below it (`eval`, `track`, `translate`, `synth`, `io`,
//! `body`, `camera`, `image`, `signal`); only `web` and the CLI import it.

pub mod calibration;
pub mod clock;
pub mod finished_take;
pub mod frame_layers;
pub mod frame_report;
pub mod framing;
pub mod plot;
pub mod session;
pub mod theme;
pub mod tracking;

//! What the app shows, still browser-free so native tests drive it: the open
//! [`session::Session`] (a recording, its settings and result), the plots laid
//! out as shapes, and the one colour theme of the plots and the 3D view. May
//! import everything below it (`eval`, `translate`, `synth`, `io`, `body`,
//! `signal`);
//! only `web` and the CLI import it.

pub mod clock;
pub mod plot;
pub mod session;
pub mod theme;

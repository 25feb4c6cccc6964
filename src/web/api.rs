//! The typed boundary between the page and the [`Player`](super::Player):
//! what crosses it as plain JavaScript objects, (de)serialised by serde
//! through serde-wasm-bindgen, their TypeScript types derived from these
//! (tsify) into `embusen.d.ts`, which `www/embusen.js` is checked against.
//! An unknown value or field is an error that names it, never a fallback.

use super::js_object::read_ts;
use serde::{Deserialize, Serialize};
use tsify::{Ts, Tsify};

use crate::app::clock::{self, Clock};
use crate::app::session;
use crate::app::theme;
use crate::io::recording::FeetChoice;
use crate::translate::MethodKind;
use crate::translate::contact::SOLE_DEPTHS_CM;
use crate::translate::hachaj::Smoothing;

/// How the original (uncorrected) skeleton is shown: over the corrected one,
/// beside it, or not at all.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, Tsify)]
#[serde(rename_all = "lowercase")]
pub enum Ghost {
    /// Drawn translucent over the corrected one.
    #[default]
    Overlay,
    /// Drawn beside it, one body-width to the side.
    Side,
    Hidden,
}

/// The settings a player's page sets, as one object (the app's
/// [`session::Settings`] hold every parameter; these are the ones the page
/// shows). `sole_depth_cm` is the contact
/// method's (`null`: estimated); `smoothing`, `window_s` and `dy_eps_cm` are
/// the paper method's; a foot `null` is detected.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
#[serde(deny_unknown_fields)]
#[tsify(missing_as_null)]
pub struct PlayerSettings {
    pub method: MethodKind,
    pub smoothing: Smoothing,
    pub window_s: f64,
    pub dy_eps_cm: f64,
    pub sole_depth_cm: Option<f64>,
    pub left_foot: Option<String>,
    pub right_foot: Option<String>,
}

/// The values a number setting may take, for the page's inputs and the check.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct NumberRange {
    pub min: f64,
    pub max: f64,
    pub step: f64,
}

impl NumberRange {
    fn check(self, name: &str, value: f64) -> Result<(), String> {
        if (self.min..=self.max).contains(&value) {
            Ok(())
        } else {
            Err(format!("{name} must be between {} and {}, not {value}", self.min, self.max))
        }
    }
}

/// The paper method's smoothing window (s).
pub const WINDOW_S: NumberRange = NumberRange { min: 0.05, max: 10.0, step: 0.05 };
/// The paper method's height difference that pins a foot (cm).
pub const DY_EPS_CM: NumberRange = NumberRange { min: 0.0, max: 100.0, step: 0.5 };

impl PlayerSettings {
    /// The settings from the page's object; an unknown value or field is an
    /// error that names it.
    pub fn from_js(value: Ts<PlayerSettings>) -> Result<PlayerSettings, String> {
        read_ts(&value, "settings")
    }

    /// The page's view of the session's settings.
    pub fn from_session(s: &session::Settings) -> PlayerSettings {
        PlayerSettings {
            method: s.method,
            smoothing: s.hachaj.smoothing,
            window_s: s.hachaj.window_s,
            dy_eps_cm: s.hachaj.dy_eps_cm,
            sole_depth_cm: s.contact.sole_depth_cm,
            left_foot: s.feet.left.clone(),
            right_foot: s.feet.right.clone(),
        }
    }

    /// `base` with these settings applied; the parameters the page does not
    /// set stay as in `base`. An error names a value out of its range.
    pub fn apply_to(&self, base: &session::Settings) -> Result<session::Settings, String> {
        WINDOW_S.check("the window", self.window_s)?;
        DY_EPS_CM.check("dyEps", self.dy_eps_cm)?;
        let mut s = base.clone();
        s.method = self.method;
        s.hachaj.smoothing = self.smoothing;
        s.hachaj.window_s = self.window_s;
        s.hachaj.dy_eps_cm = self.dy_eps_cm;
        s.contact.sole_depth_cm = self.sole_depth_cm;
        s.contact.check()?;
        s.feet = FeetChoice { left: self.left_foot.clone(), right: self.right_foot.clone() };
        Ok(s)
    }
}

/// One entry of a choice list: the value to send and what the page shows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct Choice<T> {
    pub value: T,
    pub label: String,
}

fn choice<T>(value: T, label: &str) -> Choice<T> {
    Choice { value, label: label.to_string() }
}

/// What a player starts with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
#[tsify(missing_as_null)]
pub struct Defaults {
    pub settings: PlayerSettings,
    pub speed: f64,
    pub looping: bool,
    pub follow: bool,
    /// Whether the body is drawn solid (the body model scaled to the
    /// skeleton), not as a stick figure.
    pub solid: bool,
    /// Whether the body casts its soft shadow on the floor.
    pub shadow: bool,
    pub ghost: Ghost,
}

/// Every choice the page offers, and the defaults, so the page copies none.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
#[tsify(missing_as_null)]
pub struct Options {
    pub methods: Vec<Choice<MethodKind>>,
    pub smoothings: Vec<Choice<Smoothing>>,
    /// The contact method's sole depths (cm) to choose from, besides `null`
    /// (estimated among these).
    pub sole_depths_cm: Vec<f64>,
    pub window_s: NumberRange,
    pub dy_eps_cm: NumberRange,
    pub speeds: Vec<f64>,
    pub ghosts: Vec<Choice<Ghost>>,
    /// The 3D view's legend while a camera take is shown ([`take_legend`]).
    pub take_legend: Vec<LegendEntry>,
    pub defaults: Defaults,
}

/// Whether a new player follows the hips with the camera.
pub const FOLLOW_DEFAULT: bool = false;

/// Whether a new player draws the body solid: a body reads as a body, and
/// its contacts with the floor as contacts; the stick figure shows the
/// joints the file holds.
pub const SOLID_DEFAULT: bool = true;

/// Whether a new player draws the body's shadow: without it, how high the
/// body is above the floor cannot be read in the 3D view.
pub const SHADOW_DEFAULT: bool = true;

impl Options {
    pub fn new() -> Options {
        let clock = Clock::default();
        Options {
            methods: vec![
                choice(MethodKind::Contact, "contact"),
                choice(MethodKind::Hachaj, "paper (Hachaj & Ogiela)"),
            ],
            smoothings: vec![choice(Smoothing::Faithful, "faithful (R)"), choice(Smoothing::Clean, "clean")],
            sole_depths_cm: SOLE_DEPTHS_CM.to_vec(),
            window_s: WINDOW_S,
            dy_eps_cm: DY_EPS_CM,
            speeds: clock::SPEEDS.to_vec(),
            ghosts: vec![
                choice(Ghost::Overlay, "overlay"),
                choice(Ghost::Side, "side by side"),
                choice(Ghost::Hidden, "hidden"),
            ],
            take_legend: take_legend(),
            defaults: Defaults {
                settings: PlayerSettings::from_session(&session::Settings::default()),
                speed: clock.speed(),
                looping: clock.looping(),
                follow: FOLLOW_DEFAULT,
                solid: SOLID_DEFAULT,
                shadow: SHADOW_DEFAULT,
                ghost: Ghost::default(),
            },
        }
    }
}

impl Default for Options {
    fn default() -> Self {
        Options::new()
    }
}

/// The contact method's sole depth in use.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct SoleDepth {
    /// How far the sole lies below the foot's lowest joint (cm).
    pub depth_cm: f64,
    /// Estimated from the recording, not set.
    pub estimated: bool,
}

/// A foot joint's name per foot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct FootNames {
    pub left: String,
    pub right: String,
}

/// What the info panel shows about the open recording and its result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
#[tsify(missing_as_null)]
pub struct Info {
    pub name: String,
    pub joint_names: Vec<String>,
    pub frame_count: usize,
    pub fps: f64,
    pub duration_s: f64,
    /// The foot joints in use, detected or chosen.
    pub feet: FootNames,
    pub method: MethodKind,
    /// The contact method's; `null` for the paper method and feet without toes.
    pub sole_depth: Option<SoleDepth>,
    /// Where the foot accelerations came from.
    pub accel_source: String,
    /// The reader's and the method's warnings.
    pub warnings: Vec<String>,
}

/// A file to download.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct Export {
    pub name: String,
    pub text: String,
}

/// A plot panel in pixels of the plot canvas.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct PlotPanel {
    pub x: f32,
    pub y: f32,
    pub width: f32,
    pub height: f32,
}

/// One entry of the 3D view's legend: a label and the colour it names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Tsify)]
pub struct LegendEntry {
    pub label: String,
    /// The colour, opaque, as CSS takes it (`rgba(r,g,b,a)`).
    pub color_css: String,
}

/// The 3D view's floor paths while a camera take is shown: the suit's own
/// translation, the inertial estimate (the method's result), the camera
/// track (whose colour the camera's frustum shares).
pub fn take_legend() -> Vec<LegendEntry> {
    [
        ("suit's own translation", theme::ORIGINAL),
        ("inertial estimate", theme::CORRECTED),
        ("camera track, and the camera", theme::CAMERA),
    ]
    .map(|(label, color)| LegendEntry { label: label.to_string(), color_css: color.with_alpha(255).to_css() })
    .to_vec()
}

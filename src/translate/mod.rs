//! Translation methods: where the body is on the floor, frame by frame, from
//! its pose. [`hachaj`] is Hachaj & Ogiela's heuristic exactly as their R
//! code computes it (the user's name for it is `paper`, "the paper's
//! method"); [`contact`] is embusen's own. Both return per-frame shifts
//! added to every joint; [`Method`] chooses one and [`Translated`] is its
//! outcome. May import `io`, `body`, `signal`; nothing above.

pub mod contact;
pub mod hachaj;

use glam::DVec3;

use crate::body::feet::FootJoints;
use crate::body::skeleton::Poses;
use crate::error::Error;
use crate::io::recording::{AccelSource, FeetChoice, Recording};
use contact::{ContactParams, ContactResult, contact_translation};
use hachaj::{HachajParams, HachajResult, hachaj_translation};

/// A translation method and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    /// Hachaj & Ogiela's method, as their R code computes it (`paper` to
    /// the user).
    Hachaj(HachajParams),
    /// embusen's contact method (see [`crate::translate::contact`]).
    Contact(ContactParams),
}

impl Default for Method {
    fn default() -> Self {
        Method::Contact(ContactParams::default())
    }
}

impl Method {
    /// Which method this is, without its parameters.
    pub fn kind(&self) -> MethodKind {
        match self {
            Method::Hachaj(_) => MethodKind::Hachaj,
            Method::Contact(_) => MethodKind::Contact,
        }
    }

    /// `paper` or `contact`.
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }
}

/// The choice of a translation method, as the user makes it: the page's
/// settings and the app's session carry this; [`Method`] adds the
/// parameters. (The wasm build derives its TypeScript type for the page.)
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(target_arch = "wasm32", derive(tsify::Tsify))]
#[serde(rename_all = "lowercase")]
pub enum MethodKind {
    /// embusen's contact method, the default.
    #[default]
    Contact,
    /// Hachaj & Ogiela's ([`hachaj`]), `paper` to the user.
    #[serde(rename = "paper")]
    Hachaj,
}

impl MethodKind {
    /// `paper` or `contact`, as the command line and the page name it.
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Hachaj => "paper",
            MethodKind::Contact => "contact",
        }
    }
}

/// What a method decided, frame by frame, for plots and summaries.
#[derive(Clone, Debug)]
pub enum Decisions {
    Hachaj(HachajResult),
    Contact(ContactResult),
}

impl Decisions {
    pub fn warnings(&self) -> &[String] {
        match self {
            Decisions::Hachaj(p) => &p.warnings,
            Decisions::Contact(c) => &c.warnings,
        }
    }
}

/// The outcome of a translation method on a recording.
#[derive(Clone, Debug)]
pub struct Translated {
    /// Added to every joint of frame `f` (cm).
    pub shift_cm: Vec<DVec3>,
    /// The corrected global positions.
    pub poses: Poses,
    pub feet: FootJoints,
    /// The hips joint for these feet ([`Recording::hips`]): its path is the
    /// floor path shown and measured.
    pub hips: usize,
    pub accel_source: AccelSource,
    /// What the method decided, frame by frame, for plots.
    pub decisions: Decisions,
}

impl Translated {
    /// Hachaj & Ogiela's decisions, when theirs was the method.
    pub fn hachaj(&self) -> Option<&HachajResult> {
        match &self.decisions {
            Decisions::Hachaj(p) => Some(p),
            Decisions::Contact(_) => None,
        }
    }

    /// The contact method's decisions, when it was the method.
    pub fn contact(&self) -> Option<&ContactResult> {
        match &self.decisions {
            Decisions::Contact(c) => Some(c),
            Decisions::Hachaj(_) => None,
        }
    }
}

// The methods extend `Recording` here, where they live, so that `io` knows
// nothing of them.
impl Recording {
    /// Runs Hachaj & Ogiela's method.
    pub fn translate_hachaj(&self, feet: &FeetChoice, params: &HachajParams) -> Result<Translated, Error> {
        let feet = self.feet(feet)?;
        let (accel, accel_source) = self.foot_accel_g(feet);
        let paper =
            hachaj_translation(&self.poses, feet, accel.as_ref().map(|a| a.as_slice()), self.fps, params)
                .map_err(|message| Error::whole(&self.name, message))?;
        Ok(Translated {
            poses: self.poses.shifted(&paper.shift_cm),
            shift_cm: paper.shift_cm.clone(),
            feet,
            hips: self.hips(feet),
            accel_source,
            decisions: Decisions::Hachaj(paper),
        })
    }

    /// Runs the contact method. It needs no accelerations; the suit's foot
    /// accelerometers, when attached, help it choose between two low feet.
    pub fn translate_contact(&self, feet: &FeetChoice, params: &ContactParams) -> Result<Translated, Error> {
        let feet = self.feet(feet)?;
        let hips = self.hips(feet);
        // Without accelerometers the method needs no accelerations at all.
        let (accel, accel_source) = match self.foot_accelerometers_g(feet) {
            Some((a, source)) => (Some(a), source),
            None => (None, AccelSource::Kinematic),
        };
        let accel_refs = accel.as_ref().map(|a| a.as_ref().map(|a| a.as_slice()));
        let contact =
            contact_translation(&self.poses, &self.parents, feet, hips, accel_refs, self.fps, params)
                .map_err(|message| Error::whole(&self.name, message))?;
        Ok(Translated {
            poses: self.poses.shifted(&contact.shift_cm),
            shift_cm: contact.shift_cm.clone(),
            feet,
            hips,
            accel_source,
            decisions: Decisions::Contact(contact),
        })
    }

    /// Runs `method`.
    pub fn translate(&self, feet: &FeetChoice, method: &Method) -> Result<Translated, Error> {
        match method {
            Method::Hachaj(params) => self.translate_hachaj(feet, params),
            Method::Contact(params) => self.translate_contact(feet, params),
        }
    }
}

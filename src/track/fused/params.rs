//! The fused tracker's parameters, and the energy's noise that one of them
//! is set from: apart so that the scoring and the tracker both read them.

/// embusen's tracker's parameters; each has its physical reason.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FusedParams {
    /// How wrong an inertial step may be, as a share of its length: the
    /// suit's pose moves a planted foot relative to the hips by 0.78–0.94 of
    /// the true distance at the real suit's error level (docs/contact.md).
    pub stride_error: f64,
    /// How fast the inertial path may drift where the body barely moves
    /// (cm/s): a slow slide of the planted feet.
    pub drift_cm_per_s: f64,
    /// How precisely a good fit places the silhouette (px, one σ): the body
    /// model's girths and the suit's limb angles are each off by a pixel or
    /// two at a few metres.
    pub match_sigma_px: f64,
    /// The search reaches this many σ of the prediction's uncertainty ...
    pub search_sigmas: f64,
    /// ... but at least this far (cm) ...
    pub min_search_cm: f64,
    /// ... and at most this far (cm): a step and a half of a run in one frame.
    pub max_search_cm: f64,
    /// The search's last spacing (cm).
    pub resolution_cm: f64,
    /// A contour pixel's distance to an edge counts up to this much (cm at
    /// the body's distance, so the same at any resolution): about a limb's
    /// width, past which the pixel is simply not on its edge.
    pub truncation_cm: f64,
    /// The weight of the silhouette's area off the foreground beside the
    /// contour's distance to the edges.
    pub mask_weight: f64,
    /// The weight of the foreground left uncovered in the band around the
    /// silhouette. Less than the area's: the band also catches the blur and
    /// the penumbra at the outline and the girths the body model misses
    /// (0.5 measured best of 0.3–2 on the shared scenes; 0 turns it off).
    pub uncovered_weight: f64,
    /// The band's width (cm at the body): about a forearm's radius, wide
    /// enough to be many pixels at any distance, narrow enough to stay off
    /// a neighbouring limb or person.
    pub band_cm: f64,
    /// The path search (`path`) tries candidates this far (cm) either side
    /// of each frame's fit along the line of sight (0 turns it off) ...
    pub path_reach_cm: f64,
    /// ... this far apart (cm) ...
    pub path_spacing_cm: f64,
    /// ... and takes an energy this much (px) above the frame's least as
    /// one nat of cost: by default twice [`ENERGY_NOISE_PX`], the scale at
    /// which the filter's measurement reads the same energy (a fit is as
    /// uncertain as moves its energy by the noise: ½ κ σ² = noise, so a
    /// rise ΔE is ΔE / 2·noise nats). One noise model for both.
    pub path_temperature_px: f64,
    /// Below this confidence a fit is not used.
    pub min_confidence: f64,
    /// After this long (s) without a fit used (rejected as too far from the
    /// prediction, or none believable near it), the prediction is taken for
    /// lost: the frame is searched for as the first was, and the camera is
    /// trusted again.
    pub reacquire_after_s: f64,
    /// How far the first frame's search, and a lost filter's, reaches
    /// around each guess (cm).
    pub start_search_cm: f64,
}

impl Default for FusedParams {
    fn default() -> Self {
        FusedParams::DEFAULT
    }
}

impl FusedParams {
    /// embusen's settings, measured on the shared scenes.
    pub const DEFAULT: FusedParams = FusedParams {
        stride_error: 0.15,
        drift_cm_per_s: 10.0,
        match_sigma_px: 1.5,
        search_sigmas: 3.0,
        min_search_cm: 10.0,
        max_search_cm: 60.0,
        resolution_cm: 0.5,
        truncation_cm: 10.0,
        mask_weight: 1.0,
        uncovered_weight: 0.5,
        band_cm: 5.0,
        path_reach_cm: 100.0,
        path_spacing_cm: 4.0,
        path_temperature_px: 2.0 * ENERGY_NOISE_PX,
        min_confidence: 0.2,
        reacquire_after_s: 0.5,
        start_search_cm: 80.0,
    };
}

/// How uncertain a fit's energy is (px): the mean truncated distance over a
/// few hundred contour pixels, each good to a pixel or so, but neighbours
/// err together.
pub const ENERGY_NOISE_PX: f64 = 0.1;

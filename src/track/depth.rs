//! The path's depth along the camera's lines of sight, from the soles
//! (`soles`): the silhouette's error along the line of sight is smooth in
//! time but biased, a sole's sighting noisy but unbiased; so once the path
//! is smoothed, its offset along the line of sight is estimated from the
//! sightings as a slowly changing bias and taken off ([`correct_depth`]).
//! Where no foot is on the floor (a flight) there is no sighting and the
//! silhouette is at its worst: the suit's steps carry the path there
//! between take-off and landing ([`bridge_flights`]).

use glam::DVec2;

use crate::camera::Camera;
use crate::track::soles::{SoleSighting, SoleView};

/// The longest a body is in the air (s): a long jump's flight lasts under
/// a second. A longer stretch without a foot on the floor is the pose's
/// height gone wrong, not a flight.
pub const MAX_FLIGHT_S: f64 = 1.0;

/// The silhouette's bias along the line of sight is weighed against the
/// sightings as a slowly changing quantity: sightings count with a
/// Gaussian weight of this σ in time (s) — a stride or two, short against
/// how fast the bias changes as the body turns and moves off.
pub const BIAS_TIME_SIGMA_S: f64 = 0.5;

/// One foot's sightings in consecutive frames are one pose error seen
/// again: they count as one per this long (s), about a stance's length.
pub const STANCE_S: f64 = 0.3;

/// How far the silhouette's least may be off along the line of sight
/// before any sighting (cm, one σ): 10–30 cm on the shared scenes
/// (docs/track.md). A correction is the sightings' estimate shrunk towards
/// none by how much more uncertain it is than that.
pub const PRIOR_BIAS_SIGMA_CM: f64 = 20.0;

/// `track` (floor positions per frame, cm) moved along the camera's lines
/// of sight by the bias the planted soles show: `views` (frame index into
/// `track`, view) sighted from the track, the bias estimated and taken
/// off, then sighted again from the corrected track (a sole looked for
/// where the track first stood may be found at the edge of its window)
/// and estimated once more; what it found is a [`DepthCorrection`]. Per
/// frame, each sighting's
/// offset (how far beyond the track it puts the hips) weighs by its
/// precision and by a Gaussian of [`BIAS_TIME_SIGMA_S`] in time; the
/// weighted median finds the bulk, the weighted mean of the offsets within
/// 2.5 σ of it estimates the bias, which is shrunk towards none by its
/// uncertainty against [`PRIOR_BIAS_SIGMA_CM`] (one foot's sightings within
/// [`STANCE_S`] counting as one). Frames are `dt_s` apart, filmed by
/// `camera`.
pub fn correct_depth(
    track: &mut [DVec2],
    views: &[(usize, SoleView)],
    camera: &Camera,
    dt_s: f64,
) -> DepthCorrection {
    let mut corrections: Vec<(f64, f64)> = Vec::new();
    let mut frames_sighted = 0;
    for _ in 0..2 {
        let sightings: Vec<(usize, SoleSighting)> = views
            .iter()
            .filter_map(|(i, view)| track.get(*i).and_then(|&p| view.sight(p)).map(|s| (*i, s)))
            .collect();
        let mut frames: Vec<usize> = sightings.iter().map(|(i, _)| *i).collect();
        frames.dedup();
        frames_sighted = frames.len();
        let more = bias_corrections(track, &sightings, camera, dt_s);
        corrections = if corrections.is_empty() {
            more
        } else {
            corrections.iter().zip(more).map(|(a, b)| (a.0 + b.0, b.1)).collect()
        };
    }
    DepthCorrection { per_frame: corrections, frames_sighted }
}

/// What [`correct_depth`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthCorrection {
    /// Per frame, how far the path was moved along the line of sight and
    /// how uncertain that is (cm, one σ).
    pub per_frame: Vec<(f64, f64)>,
    /// In how many frames a sole was sighted (in the last round).
    pub frames_sighted: usize,
}

/// One round of [`correct_depth`] from `sightings` (frame index into
/// `track`, in frame order): each frame's correction and its uncertainty
/// (cm along the line of sight, one σ).
fn bias_corrections(
    track: &mut [DVec2],
    sightings: &[(usize, SoleSighting)],
    camera: &Camera,
    dt_s: f64,
) -> Vec<(f64, f64)> {
    let n = track.len();
    let offsets: Vec<(usize, f64, f64)> = sightings
        .iter()
        .filter(|(i, _)| *i < n)
        .map(|&(i, s)| (i, (s.implied_hips_cm - track[i]).dot(s.along), s.sigma_cm))
        .collect();
    let reach = (4.0 * BIAS_TIME_SIGMA_S / dt_s).ceil() as usize;
    let per_stance = (STANCE_S / dt_s).max(1.0);
    let prior = PRIOR_BIAS_SIGMA_CM * PRIOR_BIAS_SIGMA_CM;
    let mut corrections = Vec::with_capacity(n);
    for (i, p) in track.iter_mut().enumerate() {
        // The sightings come in frame order: the window is a slice of them.
        let first = offsets.partition_point(|(j, _, _)| j + reach < i);
        let last = offsets.partition_point(|(j, _, _)| *j <= i + reach);
        let near: Vec<(f64, f64, f64)> = offsets[first..last]
            .iter()
            .map(|&(j, offset, sigma)| {
                let t = j.abs_diff(i) as f64 * dt_s / BIAS_TIME_SIGMA_S;
                (offset, gaussian_weight(t) / (sigma * sigma), sigma)
            })
            .collect();
        let Some(bulk) = weighted_median(&near) else {
            corrections.push((0.0, PRIOR_BIAS_SIGMA_CM));
            continue;
        };
        let kept: Vec<&(f64, f64, f64)> =
            near.iter().filter(|(o, _, s)| (o - bulk).abs() <= 2.5 * s).collect();
        let weight: f64 = kept.iter().map(|k| k.1).sum();
        if weight <= 0.0 {
            corrections.push((0.0, PRIOR_BIAS_SIGMA_CM));
            continue;
        }
        let estimate = kept.iter().map(|k| k.0 * k.1).sum::<f64>() / weight;
        // Sightings within a stance share their error: the information is
        // the weight over how many frames a stance spans. Where they scatter
        // more than their σ say (a shadow under the feet, a pose further
        // off), the estimate is as much less certain.
        let scatter = kept.iter().map(|k| k.1 * (k.0 - estimate) * (k.0 - estimate)).sum::<f64>() / weight;
        let stated = kept.iter().map(|k| k.1 * k.2 * k.2).sum::<f64>() / weight;
        let variance = per_stance / weight * (scatter / stated).max(1.0);
        let gain = prior / (prior + variance);
        let correction = gain * estimate;
        *p += camera.line_of_sight_on_floor(*p) * correction;
        corrections.push((correction, (gain * variance).sqrt()));
    }
    corrections
}

/// About `exp(−t²/2)`, by the first four terms of the series of its
/// inverse: arithmetic only, so that the CLI and the browser (whose `exp`
/// are different libraries) weigh to the same bit. Within 1 % of the
/// Gaussian's up to one σ, a little heavier beyond (0.16 for 0.14 at 2 σ).
fn gaussian_weight(t: f64) -> f64 {
    let x = 0.5 * t * t;
    1.0 / (1.0 + x * (1.0 + x * (0.5 + x / 6.0)))
}

/// The weighted median of `(value, weight, _)`; `None` without weight.
fn weighted_median(values: &[(f64, f64, f64)]) -> Option<f64> {
    let total: f64 = values.iter().map(|v| v.1).sum();
    if total <= 0.0 || !total.is_finite() {
        return None;
    }
    let mut sorted: Vec<(f64, f64)> = values.iter().map(|v| (v.0, v.1)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut running = 0.0;
    for (value, weight) in sorted {
        running += weight;
        if running >= 0.5 * total {
            return Some(value);
        }
    }
    None
}

/// `track` (floor positions per frame, cm) through each flight — a run of
/// frames where no foot of the suit's pose is on the floor (`planted`
/// false), no longer than [`MAX_FLIGHT_S`], with a planted frame on either
/// side — replaced along the camera's line of sight by the suit's own
/// steps (`steps_cm`, per frame, into it) from the take-off, their drift
/// spread evenly to meet the landing. In the air the body's height is the
/// contact method's guess, and a body placed too high fits the image best
/// nearer the camera (docs/track.md, "Height"): the silhouette's depth is
/// worst exactly there, where the sole's sightings, which anchor both
/// ends, are missing. Across `camera`'s line of sight the track stays.
pub fn bridge_flights(track: &mut [DVec2], planted: &[bool], steps_cm: &[DVec2], dt_s: f64, camera: &Camera) {
    let n = track.len().min(planted.len()).min(steps_cm.len());
    let longest = (MAX_FLIGHT_S / dt_s).round() as usize;
    let mut i = 1;
    while i < n {
        if planted[i] || !planted[i - 1] {
            i += 1;
            continue;
        }
        let (take_off, mut landing) = (i - 1, i);
        while landing < n && !planted[landing] {
            landing += 1;
        }
        if landing < n && landing - take_off - 1 <= longest {
            let mut flown = vec![DVec2::ZERO; landing - take_off + 1];
            for k in 1..flown.len() {
                flown[k] = flown[k - 1] + steps_cm[take_off + k];
            }
            let drift = track[landing] - track[take_off] - flown[flown.len() - 1];
            for k in 1..flown.len() - 1 {
                let share = k as f64 / (flown.len() - 1) as f64;
                let bridged = track[take_off] + flown[k] + drift * share;
                let p = &mut track[take_off + k];
                let along = camera.line_of_sight_on_floor(*p);
                *p += along * (bridged - *p).dot(along);
            }
        }
        i = landing + 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::soles::tests::{camera, mask_of_body_soles, one_foot};
    use crate::track::soles::view_soles;

    #[test]
    fn a_track_biased_along_the_line_of_sight_is_brought_back_by_its_soles() {
        let camera = camera();
        let (feet, body) = one_foot(DVec2::new(10.0, 20.0));
        let truth: Vec<DVec2> = (0..60).map(|i| DVec2::new(2.0 * i as f64, 0.0)).collect();
        // The silhouette's track 15 cm too far along the line of sight.
        let mut track: Vec<DVec2> =
            truth.iter().map(|&p| p + camera.line_of_sight_on_floor(p) * 15.0).collect();
        let views: Vec<(usize, SoleView)> = truth
            .iter()
            .enumerate()
            .flat_map(|(i, &p)| {
                let mask = mask_of_body_soles(&camera, &body, p);
                view_soles(&camera, &feet, &body, &mask, track[i]).into_iter().map(move |v| (i, v))
            })
            .collect();
        let corrections = correct_depth(&mut track, &views, &camera, 1.0 / 30.0).per_frame;
        // From 15 cm to within about a row's depth (3.3 cm here) and what
        // the shrinking towards no correction leaves.
        for ((p, t), (correction, sigma)) in track.iter().zip(&truth).zip(&corrections) {
            assert!(p.distance(*t) < 4.0, "{p} against {t}, corrected by {correction:.1} ± {sigma:.1}");
        }
    }

    #[test]
    fn a_flight_follows_the_suit_s_steps_along_the_line_of_sight_only() {
        let camera = camera();
        // Standing at (0, 300) and (0, 400), ten frames in the air between
        // them, the suit stepping 10 cm a frame along +z (the line of
        // sight); the silhouette's track 30 cm off in the air, and 5 cm
        // aside.
        let mut track: Vec<DVec2> =
            (0..12).map(|i| DVec2::new(5.0, 300.0 + 10.0 * i as f64 - 30.0)).collect();
        track[0] = DVec2::new(0.0, 300.0);
        track[11] = DVec2::new(0.0, 410.0);
        let planted: Vec<bool> = (0..12).map(|i| i == 0 || i == 11).collect();
        let steps = vec![DVec2::new(0.0, 10.0); 12];
        bridge_flights(&mut track, &planted, &steps, 1.0 / 30.0, &camera);
        for (i, p) in track.iter().enumerate().skip(1).take(10) {
            let expected_z = 300.0 + 10.0 * i as f64;
            assert!((p.y - expected_z).abs() < 1.0, "frame {i}: {p}");
            // Across the line of sight it stays where the track had it.
            assert!((p.x - 5.0).abs() < 0.5, "frame {i}: {p}");
        }
    }
}

//! The time offset between a video and its BVH, when the two were not
//! started together: the offset at which the suit's pose, posed at the
//! tracked positions, fits the video's frames best. A body whose limbs are
//! a tenth of a second out of step with the video fits it visibly worse,
//! so the fused energy over a few dozen frames spread across the take has
//! its least at the true offset. The energy's band term is left out: it is
//! about the body's size, so its depth, not the pose's timing.

use glam::{DVec2, DVec3};

use crate::camera::least_squares::solve_positive;
use crate::image::GreyImage;
use crate::image::pipeline::Features;
use crate::track::energy::FrameTerms;
use crate::track::fused::{FusedParams, fused_terms};
use crate::track::search::coarse_to_fine;
use crate::track::setup::TrackSetup;
use crate::track::silhouette::SilhouetteRenderer;
use crate::track::tracker::Track;

/// How many frames of a take the offset is estimated from, spread evenly.
pub const OFFSET_SAMPLES: usize = 60;

/// How far from the offset given the estimate may go (s): under half the
/// shortest stride, whose repeat would fit as well.
pub const OFFSET_REACH_S: f64 = 0.25;

/// Whether video frame `index` of a take of `frame_count` frames is one of
/// the [`OFFSET_SAMPLES`] the offset is estimated from: every
/// ⌈frame_count / OFFSET_SAMPLES⌉-th from the first.
pub fn is_offset_sample(index: usize, frame_count: usize) -> bool {
    index.is_multiple_of(frame_count.div_ceil(OFFSET_SAMPLES).max(1))
}

/// How far around each tracked position the fit is searched for each
/// offset tried (cm): the positions were tracked at another offset, and a
/// body out of step sits a little elsewhere.
const LOCAL_SEARCH_CM: f64 = 8.0;

/// The offsets are tried this far apart (s): a limb a twentieth of a second
/// out of step is visibly elsewhere in a brisk motion.
const COARSE_STEP_S: f64 = 0.05;

/// The parabola is fitted to the offsets this near the least (s).
const PARABOLA_REACH_S: f64 = 0.25;

/// The vertex of the least-squares parabola through `points` (x, y), its
/// normal equations solved by the camera's toolbox; `None` when fewer than
/// three distinct x or it opens downwards.
fn parabola_vertex(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 3 {
        return None;
    }
    // Centred on the mean x for conditioning: y = a + b·u + c·u². The
    // normal equations are positive definite for three or more distinct x.
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / points.len() as f64;
    let mut m = [0.0f64; 9];
    let mut v = [0.0f64; 3];
    for &(x, y) in points {
        let u = x - mean_x;
        let row = [1.0, u, u * u];
        for i in 0..3 {
            v[i] += row[i] * y;
            for j in 0..3 {
                m[i * 3 + j] += row[i] * row[j];
            }
        }
    }
    let fit = solve_positive(&m, &v, 3)?;
    let (b, c) = (fit[1], fit[2]);
    (c > 0.0).then(|| mean_x - b / (2.0 * c))
}

/// The offsets tried and what they cost.
#[derive(Clone, Debug, PartialEq)]
pub struct OffsetEstimate {
    /// The offset (s) to add to a video frame's time to read the BVH.
    pub offset_s: f64,
    /// Each offset tried (s) and the mean fused energy over the sampled
    /// frames there (px).
    pub tried: Vec<(f64, f64)>,
}

/// The offset within `±max_offset_s` of `setup.timing.offset_s` (that of
/// `track`) at which the pose fits `samples` (video frame index, frame) at
/// `track`'s positions best: tried every 0.05 s, then the vertex of the
/// parabola through the offsets within 0.25 s of the least; `None` when no
/// offset lets any sample be scored.
pub fn estimate_offset_s(
    setup: &TrackSetup,
    track: &Track,
    samples: &[(usize, GreyImage)],
    max_offset_s: f64,
) -> Option<OffsetEstimate> {
    let params = FusedParams::default();
    let mut renderer = SilhouetteRenderer::new(&setup.camera);
    let sampled: Vec<(usize, Features, DVec2)> = samples
        .iter()
        .filter_map(|(i, frame)| {
            let tracked = track.frames.get(*i)?;
            let f = setup.features(frame, setup.pipeline.truncate_px, "sample").ok()?;
            Some((*i, f, tracked.floor_cm))
        })
        .collect();
    let terms: Vec<(usize, FrameTerms, DVec2)> =
        sampled.iter().map(|(i, f, p)| (*i, fused_terms(&setup.camera, &params, f, *p).0, *p)).collect();
    let mut cost = |offset_s: f64| -> f64 {
        let mut total = 0.0;
        let mut scored = 0usize;
        for (i, frame_terms, p) in &terms {
            let time_s = *i as f64 / setup.timing.fps + offset_s;
            let Some(body_cm) = setup.suit.body_at(setup.suit.instant(time_s)) else { continue };
            let Ok(body) = setup.shape.pose(&body_cm, DVec3::ZERO) else { continue };
            let best = coarse_to_fine(*p, LOCAL_SEARCH_CM, 1.0, |q| {
                let silhouette = renderer.render(&body, DVec3::new(q.x, 0.0, q.y));
                frame_terms.fit(&silhouette).map_or(f64::NAN, |fit| fit.fused_energy(params.mask_weight, 0.0))
            });
            if let Some((_, e)) = best {
                total += e;
                scored += 1;
            }
        }
        // An offset that leaves most samples without a pose says little.
        if scored * 2 < terms.len().max(1) { f64::INFINITY } else { total / scored as f64 }
    };
    let centre = setup.timing.offset_s;
    let count = (max_offset_s / COARSE_STEP_S).round().max(0.0) as i64;
    let tried: Vec<(f64, f64)> =
        (-count..=count).map(|k| centre + k as f64 * COARSE_STEP_S).map(|o| (o, cost(o))).collect();
    let (best, _) =
        tried.iter().copied().filter(|(_, e)| e.is_finite()).min_by(|a, b| a.1.total_cmp(&b.1))?;
    // The cost is a sum over frames of fits that each err a little: the
    // vertex of the parabola through the offsets near the least is steadier
    // than the least itself.
    let near: Vec<(f64, f64)> = tried
        .iter()
        .copied()
        .filter(|(o, e)| e.is_finite() && (o - best).abs() <= PARABOLA_REACH_S)
        .collect();
    let offset_s = parabola_vertex(&near).filter(|v| (v - best).abs() <= PARABOLA_REACH_S).unwrap_or(best);
    Some(OffsetEstimate { offset_s, tried })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vertex_of_a_parabola_through_noisy_points() {
        let points: Vec<(f64, f64)> =
            (0..11).map(|k| 0.1 * k as f64).map(|x| (x, 2.0 + 3.0 * (x - 0.37) * (x - 0.37))).collect();
        assert!((parabola_vertex(&points).unwrap() - 0.37).abs() < 1e-9);
        let hill: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x, -y)).collect();
        assert_eq!(parabola_vertex(&hill), None);
        assert_eq!(parabola_vertex(&points[..2]), None);
    }
}

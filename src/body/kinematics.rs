//! Forward kinematics: channel values to global joint positions, in f64.
//!
//! The BVH rules we follow (the same as Blender's and three.js's importers):
//! - a joint's local transform is `translation * R(c1) * R(c2) * R(c3)` with the
//!   rotation channels composed in the order the file lists them;
//! - **position channels replace the OFFSET**, on the root and on any other
//!   joint: an axis with a position channel takes the channel's value, an axis
//!   without one keeps the OFFSET's value. (Optical exporters such as Bandai
//!   Namco's give every joint 6 channels whose positions equal the bone
//!   lengths; adding them to the OFFSET would double every bone.)

use glam::{DMat3, DQuat, DVec3};

use crate::body::skeleton::{Channel, Motion, Poses, Skeleton};

/// The `[z, y, x]` angles in degrees with `m = Rz(z) · Ry(y) · Rx(x)`: the
/// values of channels `Zrotation Yrotation Xrotation`, in that order, whose
/// [`local_rotation`] is `m`. Valid away from y = ±90°, where z and x are
/// one turn and cannot be told apart.
pub fn zyx_degrees(m: DMat3) -> [f64; 3] {
    tait_bryan_degrees([2, 1, 0], m)
}

/// The values of three rotation channels of three different axes, in the
/// channels' order, whose [`local_rotation`] is `m`: for `Zrotation
/// Xrotation Yrotation` the `[z, x, y]` with `m = Rz(z) · Rx(x) · Ry(y)`.
/// `None` unless `channels` are three rotations about three different axes
/// (a BVH may list any of the six orders; two channels of one axis, as in
/// `Zrotation Xrotation Zrotation`, are not decomposed). Valid away from a
/// middle angle of ±90°, where the first and the last are one turn.
pub fn rotation_channel_degrees(channels: [Channel; 3], m: DMat3) -> Option<[f64; 3]> {
    if channels.iter().any(|c| c.is_position()) {
        return None;
    }
    let axes = channels.map(Channel::axis);
    let distinct = axes[0] != axes[1] && axes[1] != axes[2] && axes[0] != axes[2];
    distinct.then(|| tait_bryan_degrees(axes, m))
}

/// The angles (degrees) of `m = R_i(a) · R_j(b) · R_k(c)` for three
/// different axes `[i, j, k]` (0 = X): with `s` = +1 when `i j k` run
/// cyclically (X Y Z, Y Z X, Z X Y) and −1 otherwise, `m[i][k] = s·sin b`,
/// `m[j][k] / m[k][k] = −s·tan a` and `m[i][j] / m[i][i] = −s·tan c` (rows
/// first). For `[2, 1, 0]` these are the operations [`zyx_degrees`] always
/// did, so its results are bit for bit those of before.
fn tait_bryan_degrees([i, j, k]: [usize; 3], m: DMat3) -> [f64; 3] {
    let cyclic = (i + 1) % 3 == j;
    // Negation is exact: s·v costs no rounding either way.
    let signed = |v: f64| if cyclic { v } else { -v };
    let row_col = |row: usize, col: usize| m.col(col)[row];
    let middle = libm::asin(signed(row_col(i, k)).clamp(-1.0, 1.0));
    let (cos_first, sin_first) = (row_col(k, k), -signed(row_col(j, k)));
    // At a middle angle of ±90° (cos b below 1e-12) both are rounding
    // noise and only a ± c is told: c = 0 and a from the j column, which
    // R_j leaves alone.
    if cos_first * cos_first + sin_first * sin_first < 1e-24 {
        let first = libm::atan2(signed(row_col(k, j)), row_col(j, j));
        return [first.to_degrees(), middle.to_degrees(), 0.0];
    }
    let first = libm::atan2(sin_first, cos_first);
    let last = libm::atan2(-signed(row_col(i, j)), row_col(i, i));
    [first.to_degrees(), middle.to_degrees(), last.to_degrees()]
}

/// The rotation of one joint in one frame, from its rotation channels.
pub fn local_rotation(channels: &[Channel], values: &[f64]) -> DMat3 {
    let mut parent_from_joint = DMat3::IDENTITY;
    for (&channel, &degrees) in channels.iter().zip(values) {
        let angle = degrees.to_radians();
        let r = match channel {
            Channel::Xrotation => DMat3::from_rotation_x(angle),
            Channel::Yrotation => DMat3::from_rotation_y(angle),
            Channel::Zrotation => DMat3::from_rotation_z(angle),
            _ => continue,
        };
        parent_from_joint *= r;
    }
    parent_from_joint
}

/// The translation of one joint from its parent: the OFFSET with any position
/// channel replacing its axis.
pub fn local_translation(offset_cm: DVec3, channels: &[Channel], values: &[f64]) -> DVec3 {
    let mut t = offset_cm;
    for (&channel, &value) in channels.iter().zip(values) {
        if channel.is_position() {
            t[channel.axis()] = value;
        }
    }
    t
}

/// Every joint's global rotation, frame after frame (`frame * joints +
/// joint`): its parents' rotations composed with its own channels'.
pub fn world_rotations(skeleton: &Skeleton, motion: &Motion) -> Vec<DQuat> {
    let n = skeleton.joint_count();
    let mut world = Vec::with_capacity(n * motion.frame_count());
    for f in 0..motion.frame_count() {
        let values = motion.frame(f);
        let start = world.len();
        for j in 0..n {
            let first = skeleton.first_channel[j];
            let channels = &skeleton.channels[j];
            let local = local_rotation(channels, &values[first..first + channels.len()]);
            let parent = skeleton.parents[j].map_or(DMat3::IDENTITY, |p| DMat3::from_quat(world[start + p]));
            world.push(DQuat::from_mat3(&(parent * local)).normalize());
        }
    }
    world
}

/// Global positions of every joint (end sites included) in every frame.
pub fn forward_kinematics(skeleton: &Skeleton, motion: &Motion) -> Poses {
    let joint_count = skeleton.joint_count();
    let frame_count = motion.frame_count();
    let mut positions_cm = Vec::with_capacity(joint_count * frame_count);
    // Per-joint world rotations of the current frame, reused across frames.
    let mut world_from_joint_rot = vec![DMat3::IDENTITY; joint_count];
    for f in 0..frame_count {
        let values = motion.frame(f);
        let frame_start = positions_cm.len();
        for j in 0..joint_count {
            let channels = &skeleton.channels[j];
            let first = skeleton.first_channel[j];
            let joint_values = &values[first..first + channels.len()];
            let translation = local_translation(skeleton.offsets_cm[j], channels, joint_values);
            let rotation = local_rotation(channels, joint_values);
            let (point_in_world, world_rot) = match skeleton.parents[j] {
                None => (translation, rotation),
                Some(p) => {
                    let parent_rot = world_from_joint_rot[p];
                    (positions_cm[frame_start + p] + parent_rot * translation, parent_rot * rotation)
                }
            };
            world_from_joint_rot[j] = world_rot;
            positions_cm.push(point_in_world);
        }
    }
    Poses { joint_count, positions_cm }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formulas `zyx_degrees` had before it was one case of six: the
    /// demo's bytes rest on them.
    fn zyx_degrees_as_before(m: DMat3) -> [f64; 3] {
        let y = libm::asin((-m.x_axis.z).clamp(-1.0, 1.0));
        let z = libm::atan2(m.x_axis.y, m.x_axis.x);
        let x = libm::atan2(m.y_axis.z, m.z_axis.z);
        [z.to_degrees(), y.to_degrees(), x.to_degrees()]
    }

    #[test]
    fn zyx_degrees_are_bit_for_bit_as_before() {
        let channels = [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation];
        for angles in [[130.0, -40.0, 75.0], [-0.0, 0.0, -0.0], [179.9, 89.99, -179.9], [1e-9, -3.0, 45.0]] {
            let m = local_rotation(&channels, &angles);
            let [old, new] = [zyx_degrees_as_before(m), zyx_degrees(m)].map(|a| a.map(f64::to_bits));
            assert_eq!(old, new, "{angles:?}");
            assert_eq!(rotation_channel_degrees(channels, m).map(|a| a.map(f64::to_bits)), Some(old));
        }
    }

    #[test]
    fn every_order_of_three_axes_round_trips_through_its_channels() {
        use Channel::{Xrotation as X, Yrotation as Y, Zrotation as Z};
        let angles = [130.0, -40.0, 75.0];
        for channels in [[Z, X, Y], [Y, X, Z], [X, Y, Z], [X, Z, Y], [Y, Z, X], [Z, Y, X]] {
            let m = local_rotation(&channels, &angles);
            let back = rotation_channel_degrees(channels, m).unwrap();
            for (a, b) in angles.iter().zip(back) {
                assert!((a - b).abs() < 1e-9, "{channels:?}: {angles:?} came back as {back:?}");
            }
        }
    }

    #[test]
    fn a_middle_angle_of_90_degrees_keeps_the_rotation() {
        use Channel::{Xrotation as X, Yrotation as Y, Zrotation as Z};
        for channels in [[Z, X, Y], [Y, X, Z], [Z, Y, X]] {
            for angles in [[30.0, 90.0, 20.0], [-50.0, -90.0, 10.0]] {
                let m = local_rotation(&channels, &angles);
                let back = local_rotation(&channels, &rotation_channel_degrees(channels, m).unwrap());
                assert!(
                    (back - m).abs().to_cols_array().iter().all(|d| *d < 1e-12),
                    "{channels:?} {angles:?}"
                );
            }
        }
    }

    #[test]
    fn two_channels_of_one_axis_are_not_decomposed() {
        use Channel::{Xposition, Xrotation, Zrotation};
        let m = DMat3::from_rotation_z(0.3);
        assert_eq!(rotation_channel_degrees([Zrotation, Xrotation, Zrotation], m), None);
        assert_eq!(rotation_channel_degrees([Zrotation, Xrotation, Xposition], m), None);
    }

    #[test]
    fn zyx_degrees_round_trips_through_the_channels() {
        let channels = [Channel::Zrotation, Channel::Yrotation, Channel::Xrotation];
        let angles = [130.0, -40.0, 75.0];
        let back = zyx_degrees(local_rotation(&channels, &angles));
        for (a, b) in angles.iter().zip(back) {
            assert!((a - b).abs() < 1e-9, "{angles:?} came back as {back:?}");
        }
    }
}

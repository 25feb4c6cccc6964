//! The 3D view: three-d rendering into a canvas that JavaScript created.
//!
//! Skeletons are drawn from two instanced meshes (a unit sphere for joints, a
//! unit cylinder for bones), so a frame costs a handful of draw calls whatever
//! the skeleton. The floor is flat geometry: one quad with a repeating grid
//! texture, and the hips trails as ribbons of two triangles a segment. (Trails
//! of cylinders and grid lines of cylinders cost software WebGL ~150 ms a frame.) Positions arrive in the recording's
//! centimetres and are drawn in metres, turned upright by `world_from_recording`.
//!
//! Under the body a soft shadow: one blurred disc per joint, straight below
//! it on the floor, darker and tighter the nearer the joint is to the floor
//! (the look of a contact shadow under a light from above: a jump lifts the
//! feet's discs away, a stance presses them dark). One instanced quad, a
//! few dozen instances: no shadow map, whose depth pass would double the
//! software GPU's work a frame.
//!
//! A camera-tracked take ([`CameraTake`]) replaces the corrected stick figure
//! with the body model, solid, at the camera track's hips (one mesh, rebuilt
//! when the frame changes), draws the camera's frustum (eight thin
//! cylinders), and adds the camera track's floor path.

use glam::DVec3;
use three_d::*;

use crate::app::theme::{self, Rgba};
use crate::body::feet::Foot;
use crate::body::shape::BodyShape;
use crate::body::skeleton::Poses;
use crate::web::api::Ghost;

const CM_TO_M: f32 = 0.01;
const BONE_RADIUS_M: f32 = 0.018;
const JOINT_RADIUS_M: f32 = 0.028;
const PINNED_RADIUS_M: f32 = 0.06;
/// Trails are decimated to at most this many segments, so that a 100,000-frame
/// recording draws as fast as a short one.
const MAX_TRAIL_SEGMENTS: usize = 3000;
const TRAIL_HALF_WIDTH_M: f32 = 0.012;

/// The 3D view's vertical field of view.
const VERTICAL_FOV_DEG: f32 = 45.0;
/// How tall the body is framed above the floor (m), with its paths.
const FRAMED_HEIGHT_M: f32 = 2.0;
/// Grid spacing on the floor.
const GRID_CELL_M: f32 = 0.5;
/// Meridians of each sphere and sides of each cone of the solid body: round
/// enough, and a few thousand triangles that software WebGL draws at once.
const BODY_SEGMENTS: u32 = 10;
/// A joint's shadow: its radius on the floor, and how fast it widens and
/// fades with the joint's height above the floor (m).
const SHADOW_RADIUS_M: f32 = 0.12;
const SHADOW_WIDENING_PER_M: f32 = 0.25;
const SHADOW_FADE_HEIGHT_M: f32 = 0.7;
/// Joints higher than this above the floor cast no disc of their own (the
/// hips' stands for the trunk): a software GPU pays for every blended pixel,
/// and the trunk's wide, faint discs would cover one another a dozen times.
const SHADOW_MAX_HEIGHT_M: f32 = 0.6;
/// The camera frustum's lines, as cylinders of this radius.
const FRUSTUM_RADIUS_M: f32 = 0.012;

/// A camera-tracked take of the open recording, as the view shows it.
pub struct CameraTake {
    /// Where the camera track puts the hips joint, per frame of the
    /// recording (its own coordinates, cm); a non-finite one draws no body.
    pub hips_cm: Vec<DVec3>,
    /// The camera's frustum: line segments, both ends in recording cm.
    pub frustum_cm: Vec<[DVec3; 2]>,
}

/// A theme colour as three-d takes it.
const fn srgba(Rgba(r, g, b, a): Rgba) -> Srgba {
    Srgba::new(r, g, b, a)
}

/// An orbiting camera: it looks at `target` from `distance_m` away, turned by
/// `yaw` about the up axis and raised by `pitch`.
struct Orbit {
    target: Vec3,
    yaw: f32,
    pitch: f32,
    distance_m: f32,
}

impl Orbit {
    fn position(&self) -> Vec3 {
        let horizontal = self.distance_m * self.pitch.cos();
        self.target
            + vec3(
                horizontal * self.yaw.sin(),
                self.distance_m * self.pitch.sin(),
                horizontal * self.yaw.cos(),
            )
    }
}

pub struct Scene {
    context: Context,
    camera: Camera,
    orbit: Orbit,
    pub follow: bool,
    /// Whether the corrected body is drawn solid ([`Scene::set_solid`]).
    solid: bool,
    /// The recording's body model, when one can be read from its skeleton:
    /// drawn solid, and at a camera take's track.
    pub shape: Option<BodyShape>,
    pub ghost: Ghost,
    /// Rotation that stands the recording up (Z-up files) in three-d's Y-up world.
    world_from_recording: Mat4,
    joints: Gm<InstancedMesh, PhysicalMaterial>,
    bones: Gm<InstancedMesh, PhysicalMaterial>,
    ghost_joints: Gm<InstancedMesh, PhysicalMaterial>,
    ghost_bones: Gm<InstancedMesh, PhysicalMaterial>,
    /// Hips trails: rebuilt only when the recording changes.
    trails: Gm<Mesh, ColorMaterial>,
    /// The floor: one quad under the whole path, textured with one grid cell.
    grid: Gm<Mesh, ColorMaterial>,
    /// The floor's height in the world (m): the shadows lie on it.
    floor_y: f32,
    /// Whether the body casts its soft shadow ([`Scene::set_shadow`]).
    shadow: bool,
    /// The shadow: a soft disc under each joint of the body drawn.
    shadows: Gm<InstancedMesh, ColorMaterial>,
    /// The hips joint, which follow mode keeps in view.
    hips: usize,
    ambient: AmbientLight,
    sun: DirectionalLight,
    /// What the view frames: a sphere around the orbit's target holding the
    /// floor paths and the body above them (m), and the view's aspect it was
    /// last fitted to (NaN: fit again at the next render).
    framed_radius_m: f32,
    framed_aspect: f32,
    /// Sideways offset of the ghost in side-by-side mode (m).
    side_offset: Vec3,
    /// The camera-tracked take shown, if any, and its camera's frustum.
    take: Option<CameraTake>,
    /// The solid body, of frame `body_frame`, shown when that frame has one.
    body: Gm<Mesh, PhysicalMaterial>,
    body_frame: Option<usize>,
    body_shown: bool,
    frustum: Gm<InstancedMesh, PhysicalMaterial>,
}

/// How a material draws: a transparent one blended, leaving the depth buffer alone.
fn render_states(transparent: bool) -> RenderStates {
    if transparent {
        RenderStates { write_mask: WriteMask::COLOR, blend: Blend::TRANSPARENCY, ..Default::default() }
    } else {
        RenderStates::default()
    }
}

/// A lit material of one colour. The materials are built field by field as
/// three-d's constructors from a `CpuMaterial` build them (the same light
/// model and render states): those bring its code to upload a texture of
/// any pixel format, ~3 KB gzipped of the player's download.
fn material(color: Srgba, transparent: bool) -> PhysicalMaterial {
    PhysicalMaterial {
        albedo: color,
        roughness: 0.7,
        metallic: 0.0,
        render_states: render_states(transparent),
        is_transparent: transparent,
        ..Default::default()
    }
}

/// A material of one colour, unlit (times the vertex colours, when the mesh has them).
fn flat(color: Srgba, texture: Option<Texture2DRef>, transparent: bool) -> ColorMaterial {
    ColorMaterial { color, texture, render_states: render_states(transparent), is_transparent: transparent }
}

fn instanced(
    context: &Context,
    mesh: &CpuMesh,
    color: Srgba,
    transparent: bool,
) -> Gm<InstancedMesh, PhysicalMaterial> {
    Gm::new(InstancedMesh::new(context, &Instances::default(), mesh), material(color, transparent))
}

/// A cylinder from `a` to `b` of radius `r` (three-d's unit cylinder runs
/// along +X from 0 to 1 with radius 1).
fn segment(a: Vec3, b: Vec3, r: f32) -> Mat4 {
    let d = b - a;
    let length = d.magnitude();
    if length < 1e-6 {
        return Mat4::from_translation(a) * Mat4::from_scale(0.0);
    }
    Mat4::from_translation(a)
        * Mat4::from(Quat::from_arc(vec3(1.0, 0.0, 0.0), d / length, None))
        * Mat4::from_nonuniform_scale(length, r, r)
}

fn ball(p: Vec3, r: f32) -> Mat4 {
    Mat4::from_translation(p) * Mat4::from_scale(r)
}

/// Appends a flat ribbon along `points` (on the floor, `TRAIL_HALF_WIDTH_M`
/// to each side) to `mesh`, as unindexed triangles.
fn add_ribbon(mesh: &mut CpuMesh, points: &[Vec3], color: Srgba) {
    let (Positions::F32(positions), Some(colors)) = (&mut mesh.positions, &mut mesh.colors) else { return };
    for w in points.windows(2) {
        let along = vec3(w[1].x - w[0].x, 0.0, w[1].z - w[0].z);
        if along.magnitude2() < 1e-12 {
            continue;
        }
        let side = vec3(-along.z, 0.0, along.x).normalize() * TRAIL_HALF_WIDTH_M;
        let [a, b, c, d] = [w[0] - side, w[0] + side, w[1] + side, w[1] - side];
        positions.extend([a, b, c, a, c, d]);
        colors.extend([color; 6]);
    }
}

/// A rectangle on the floor at height `y` over `x` and `z` (each from, to),
/// facing up, its texture coordinates `uv_of` each corner.
fn floor_quad(x: (f32, f32), z: (f32, f32), y: f32, uv_of: impl Fn(Vec3) -> Vec2) -> CpuMesh {
    let corners = [vec3(x.0, y, z.0), vec3(x.1, y, z.0), vec3(x.1, y, z.1), vec3(x.0, y, z.1)];
    CpuMesh {
        positions: Positions::F32(corners.to_vec()),
        indices: Indices::U8(vec![0, 2, 1, 0, 3, 2]),
        uvs: Some(corners.iter().map(|c| uv_of(*c)).collect()),
        ..Default::default()
    }
}

/// A soft disc as a texture: black, opaque at the centre and fading to
/// nothing at the edge ((1 − r)², r the distance from the centre over the
/// radius), as a shadow cast by a light the size of the sky.
fn soft_disc(context: &Context) -> Texture2DRef {
    const SIZE: usize = 32;
    let data: Vec<[u8; 4]> = (0..SIZE * SIZE)
        .map(|i| {
            let centred = |v: usize| (v as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
            let r = centred(i % SIZE).hypot(centred(i / SIZE)).min(1.0);
            [0, 0, 0, (255.0 * (1.0 - r).powi(2)) as u8]
        })
        .collect();
    square_texture(context, SIZE, &data, None, Wrapping::ClampToEdge)
}

/// A `size` × `size` texture of RGBA texels `data`, filtered linearly (and
/// mipmapped when asked), wrapped at its edges by `wrapping`.
fn square_texture(
    context: &Context,
    size: usize,
    data: &[[u8; 4]],
    mipmap: Option<Mipmap>,
    wrapping: Wrapping,
) -> Texture2DRef {
    let size = size as u32;
    let texture = Texture2D::new_empty::<[u8; 4]>(
        context,
        size,
        size,
        Interpolation::Linear,
        Interpolation::Linear,
        mipmap,
        wrapping,
        wrapping,
    );
    texture.fill(data);
    Texture2DRef::from_texture(texture)
}

/// One grid cell as a texture: a line along two edges, transparent inside;
/// repeated across the floor quad by its texture coordinates. Its texels are
/// linear sRGB, as three-d's shaders read them.
fn grid_cell(context: &Context) -> Texture2DRef {
    const SIZE: usize = 64;
    let Rgba(r, g, b, a) = theme::FLOOR_GRID;
    let line: [u8; 4] = Srgba::from(Srgba::new(r, g, b, a).to_linear_srgb()).into();
    let data: Vec<[u8; 4]> =
        (0..SIZE * SIZE).map(|i| if i % SIZE < 2 || i / SIZE < 2 { line } else { [0, 0, 0, 0] }).collect();
    square_texture(context, SIZE, &data, Some(Mipmap::default()), Wrapping::Repeat)
}

impl Scene {
    pub fn new(context: Context) -> Scene {
        let sphere = CpuMesh::sphere(12);
        let cylinder = CpuMesh::cylinder(10);
        let camera = Camera::new_perspective(
            Viewport::new_at_origo(1, 1),
            vec3(0.0, 2.0, 5.0),
            vec3(0.0, 1.0, 0.0),
            vec3(0.0, 1.0, 0.0),
            degrees(VERTICAL_FOV_DEG),
            0.05,
            500.0,
        );
        let trails = Gm::new(Mesh::new(&context, &CpuMesh::square()), flat(Srgba::WHITE, None, false));
        let grid = Gm::new(
            Mesh::new(&context, &CpuMesh::square()),
            flat(Srgba::WHITE, Some(grid_cell(&context)), true),
        );
        // A unit square on the floor (y = 0, x and z from -1 to 1).
        let disc = floor_quad((-1.0, 1.0), (-1.0, 1.0), 0.0, |c| vec2((c.x + 1.0) / 2.0, (c.z + 1.0) / 2.0));
        let shadows = Gm::new(
            InstancedMesh::new(&context, &Instances::default(), &disc),
            flat(srgba(theme::FLOOR_SHADOW), Some(soft_disc(&context)), true),
        );
        Scene {
            joints: instanced(&context, &sphere, srgba(theme::CORRECTED_SKELETON), false),
            bones: instanced(&context, &cylinder, srgba(theme::CORRECTED_SKELETON), false),
            ghost_joints: instanced(&context, &sphere, srgba(theme::ORIGINAL_SKELETON), true),
            ghost_bones: instanced(&context, &cylinder, srgba(theme::ORIGINAL_SKELETON), true),
            frustum: instanced(&context, &cylinder, srgba(theme::CAMERA), false),
            body: Gm::new(
                Mesh::new(&context, &CpuMesh::square()),
                material(srgba(theme::CORRECTED_SKELETON), false),
            ),
            body_frame: None,
            body_shown: false,
            trails,
            grid,
            floor_y: 0.0,
            shadow: true,
            shadows,
            hips: 0,
            ambient: AmbientLight::new(&context, 0.45, Srgba::WHITE),
            sun: DirectionalLight::new(&context, 2.2, Srgba::WHITE, vec3(-0.4, -1.0, -0.6)),
            camera,
            orbit: Orbit { target: vec3(0.0, 1.0, 0.0), yaw: 0.6, pitch: 0.35, distance_m: 6.0 },
            follow: false,
            solid: false,
            shape: None,
            ghost: Ghost::Overlay,
            world_from_recording: Mat4::identity(),
            side_offset: vec3(1.2, 0.0, 0.0),
            framed_radius_m: 3.0,
            framed_aspect: f32::NAN,
            take: None,
            context,
        }
    }

    fn to_world(&self, p_cm: DVec3) -> Vec3 {
        let p = vec3(p_cm.x as f32, p_cm.y as f32, p_cm.z as f32) * CM_TO_M;
        (self.world_from_recording * p.extend(1.0)).truncate()
    }

    /// A direction of the recording (a normal) in the world: turned, not scaled.
    fn direction_to_world(&self, d: glam::Vec3) -> Vec3 {
        (self.world_from_recording * vec3(d.x, d.y, d.z).extend(0.0)).truncate()
    }

    /// Shows `take` (or none) from the next [`Scene::set_recording`] on,
    /// which must follow: its path joins the framing, its camera the floor.
    pub fn set_take(&mut self, take: Option<CameraTake>) {
        self.take = take;
        self.body_frame = None;
    }

    /// Draws the corrected body solid, or as sticks.
    pub fn set_solid(&mut self, solid: bool) {
        self.solid = solid;
        self.body_frame = None;
    }

    /// Lets the body cast its soft shadow on the floor, or not.
    pub fn set_shadow(&mut self, shadow: bool) {
        self.shadow = shadow;
    }

    /// Whether a camera-tracked take is shown.
    pub fn has_take(&self) -> bool {
        self.take.is_some()
    }

    /// Prepares the static parts for a new recording: up axis, floor grid,
    /// hips trails, and a camera that frames the whole floor path.
    pub fn set_recording(&mut self, original: &Poses, corrected: &Poses, hips: usize, up_is_z: bool) {
        // Z-up files: rotate -90° about X so +Z becomes +Y.
        self.world_from_recording =
            if up_is_z { Mat4::from_angle_x(degrees(-90.0)) } else { Mat4::identity() };
        let hips_before: Vec<Vec3> = original.trajectory(hips).iter().map(|p| self.to_world(*p)).collect();
        let hips_after: Vec<Vec3> = corrected.trajectory(hips).iter().map(|p| self.to_world(*p)).collect();
        let hips_camera: Vec<Vec3> = self
            .take
            .as_ref()
            .map_or_else(Vec::new, |t| t.hips_cm.iter().map(|p| self.to_world(*p)).collect());
        let frustum: Vec<[Vec3; 2]> = self.take.as_ref().map_or_else(Vec::new, |t| {
            t.frustum_cm.iter().map(|[a, b]| [self.to_world(*a), self.to_world(*b)]).collect()
        });
        // Floor height: the lowest joint of the corrected recording's first frame.
        let floor_y = corrected
            .frame(0)
            .iter()
            .map(|p| self.to_world(*p).y)
            .fold(f32::INFINITY, f32::min)
            .clamp(-10.0, 0.0);
        // The view frames the body's paths; the floor reaches under the
        // camera too, which may stand metres away, out of the picture.
        let (mut min, mut max) =
            (vec3(f32::INFINITY, 0.0, f32::INFINITY), vec3(f32::NEG_INFINITY, 0.0, f32::NEG_INFINITY));
        let path_points = hips_before.len() + hips_after.len() + hips_camera.len();
        let mut paths = None;
        let points =
            hips_before.iter().chain(&hips_after).chain(&hips_camera).chain(frustum.iter().flatten());
        for (k, p) in points.enumerate() {
            if k == path_points {
                paths = Some((min, max));
            }
            if p.x.is_finite() && p.z.is_finite() {
                min = vec3(min.x.min(p.x), 0.0, min.z.min(p.z));
                max = vec3(max.x.max(p.x), 0.0, max.z.max(p.z));
            }
        }
        if !min.x.is_finite() {
            (min, max) = (vec3(-1.0, 0.0, -1.0), vec3(1.0, 0.0, 1.0));
        }
        let (path_min, path_max) = paths.filter(|(m, _)| m.x.is_finite()).unwrap_or((min, max));
        // The grid reaches one metre beyond the paths, snapped to whole cells
        // so that the lines stay put when the recording changes.
        let snap = |v: f32, up: bool| {
            let cells = v / GRID_CELL_M;
            (if up { cells.ceil() } else { cells.floor() }) * GRID_CELL_M
        };
        let (x0, x1) = (snap(min.x - 1.0, false), snap(max.x + 1.0, true));
        let (z0, z1) = (snap(min.z - 1.0, false), snap(max.z + 1.0, true));
        let quad = floor_quad((x0, x1), (z0, z1), floor_y, |c| vec2(c.x / GRID_CELL_M, c.z / GRID_CELL_M));
        self.grid.geometry = Mesh::new(&self.context, &quad);
        self.floor_y = floor_y;
        let mut ribbons =
            CpuMesh { positions: Positions::F32(Vec::new()), colors: Some(Vec::new()), ..Default::default() };
        // Each trail a millimetre above the one before, so that where they
        // cross the later one shows, not whichever the depth test picks.
        for (trail, color, above_floor_m) in [
            (&hips_before, theme::ORIGINAL, 0.003),
            (&hips_after, theme::CORRECTED, 0.004),
            (&hips_camera, theme::CAMERA, 0.005),
        ] {
            let stride = (trail.len() / MAX_TRAIL_SEGMENTS).max(1);
            let points: Vec<Vec3> = trail
                .iter()
                .step_by(stride)
                .filter(|p| p.x.is_finite() && p.z.is_finite())
                .map(|p| vec3(p.x, floor_y + above_floor_m, p.z))
                .collect();
            add_ribbon(&mut ribbons, &points, srgba(color));
        }
        self.trails.geometry = Mesh::new(&self.context, &ribbons);
        self.hips = hips;
        // Frame the paths and the body on them: look at their centre from
        // far enough away for the view's shape (fitted at the next render).
        let centre = (path_min + path_max) * 0.5;
        let size = path_max - path_min;
        self.orbit.target = vec3(centre.x, floor_y + FRAMED_HEIGHT_M / 2.0, centre.z);
        self.framed_radius_m = 0.5 * size.x.hypot(size.z).hypot(FRAMED_HEIGHT_M).max(2.4);
        self.framed_aspect = f32::NAN;
        let height = hips_after.first().map_or(1.0, |h| h.y - floor_y);
        self.side_offset = vec3(height.clamp(0.5, 2.0) * 1.2, 0.0, 0.0);
        let finite = |p: &Vec3| p.x.is_finite() && p.y.is_finite() && p.z.is_finite();
        let lines = frustum
            .iter()
            .filter(|[a, b]| finite(a) && finite(b))
            .map(|[a, b]| segment(*a, *b, FRUSTUM_RADIUS_M))
            .collect();
        self.frustum.set_instances(&Instances { transformations: lines, ..Default::default() });
        self.body_frame = None;
    }

    /// Moves the skeletons to frame `f`, highlighting the pinned foot: its
    /// joint, and which foot it is. With a take, the corrected skeleton's
    /// place is the solid body's: the original pose moved by the camera
    /// track's hips less the original's (its mesh made again only when `f`
    /// is not the frame it was made for).
    pub fn set_frame(
        &mut self,
        original: &Poses,
        corrected: &Poses,
        parents: &[Option<usize>],
        f: usize,
        pinned: Option<(usize, Foot)>,
    ) {
        if f >= corrected.frame_count() || f >= original.frame_count() {
            return;
        }
        // Where the body is drawn: the corrected pose, or the take's (none in
        // a frame the camera track has no hips for).
        let take_shift_cm = self.take.as_ref().map(|take| {
            let tracked_cm = take.hips_cm.get(f).copied().unwrap_or(DVec3::NAN);
            let hips_cm = original.frame(f).get(self.hips).copied().unwrap_or(DVec3::NAN);
            Some(tracked_cm - hips_cm).filter(|shift| shift.is_finite())
        });
        let solid: Vec<Vec3> = match take_shift_cm {
            None => corrected.frame(f).iter().map(|p| self.to_world(*p)).collect(),
            Some(Some(shift_cm)) => original.frame(f).iter().map(|p| self.to_world(*p + shift_cm)).collect(),
            Some(None) => Vec::new(),
        };
        // Solid: the take's body at its track, or the corrected one (the
        // original pose and the shift that corrects it); sticks otherwise.
        let body = match take_shift_cm {
            Some(shift_cm) => Some(shift_cm),
            None if self.solid && self.shape.is_some() => {
                let at = |poses: &Poses| poses.frame(f).get(self.hips).copied().unwrap_or(DVec3::NAN);
                Some(Some(at(corrected) - at(original)).filter(|shift| shift.is_finite()))
            }
            None => None,
        };
        let (mut joints, bones) = match body {
            None => self.skeleton_instances(&solid, parents, Vec3::new(0.0, 0.0, 0.0)),
            Some(_) => (Vec::new(), Vec::new()),
        };
        let mut colors = vec![srgba(theme::CORRECTED_SKELETON); joints.len()];
        if let Some((joint, foot)) = pinned
            && let Some(p) = solid.get(joint)
        {
            joints.push(ball(*p, PINNED_RADIUS_M));
            colors.push(srgba(theme::FEET[foot]));
        }
        self.joints.set_instances(&Instances {
            transformations: joints,
            colors: Some(colors),
            ..Default::default()
        });
        self.bones.set_instances(&Instances { transformations: bones, ..Default::default() });
        self.cast_shadow(&solid, parents);
        if let Some(shift_cm) = body {
            self.set_body(original, f, shift_cm);
        }
        self.body_shown &= body.is_some();
        if self.ghost != Ghost::Hidden {
            let ghost: Vec<Vec3> = original.frame(f).iter().map(|p| self.to_world(*p)).collect();
            let offset = match (self.ghost, solid.get(self.hips), ghost.get(self.hips)) {
                (Ghost::Side, Some(solid), Some(ghost)) => *solid + self.side_offset - *ghost,
                _ => Vec3::new(0.0, 0.0, 0.0),
            };
            let (gj, gb) = self.skeleton_instances(&ghost, parents, offset);
            self.ghost_joints.set_instances(&Instances { transformations: gj, ..Default::default() });
            self.ghost_bones.set_instances(&Instances { transformations: gb, ..Default::default() });
        }
        if self.follow
            && let Some(&hips) = solid.get(self.hips)
        {
            self.orbit.target = vec3(hips.x, self.orbit.target.y, hips.z);
            self.orbit.distance_m = self.orbit.distance_m.min(6.0);
        }
    }

    /// The shadow of the body whose joints are at `points` (world, m): a
    /// soft disc on the floor under the hips and under each joint of the
    /// body within [`SHADOW_MAX_HEIGHT_M`] of the floor (none above the
    /// hips, as [`Scene::skeleton_instances`]), wider and fainter the higher
    /// the joint.
    fn cast_shadow(&mut self, points: &[Vec3], parents: &[Option<usize>]) {
        let above_hips = crate::body::feet::above_hips(parents, self.hips);
        let (transformations, colors) = points
            .iter()
            .enumerate()
            .filter(|(j, p)| !above_hips.contains(j) && p.x.is_finite() && p.y.is_finite() && p.z.is_finite())
            .map(|(j, p)| (j, p, (p.y - self.floor_y).max(0.0)))
            .filter(|&(j, _, height_m)| j == self.hips || height_m <= SHADOW_MAX_HEIGHT_M)
            .map(|(_, p, height_m)| {
                let radius_m = SHADOW_RADIUS_M + SHADOW_WIDENING_PER_M * height_m;
                let darkness = 1.0 / (1.0 + height_m / SHADOW_FADE_HEIGHT_M).powi(2);
                // A millimetre above the floor: over the grid, under the trails.
                let at = vec3(p.x, self.floor_y + 0.001, p.z);
                (ball(at, radius_m), Srgba::new(255, 255, 255, (255.0 * darkness) as u8))
            })
            .unzip();
        self.shadows.set_instances(&Instances {
            transformations,
            colors: Some(colors),
            ..Default::default()
        });
    }

    /// The solid body in frame `f`: the body model in the original pose of
    /// `f` moved by `shift_cm` (none when `None`), meshed again only when
    /// the mesh is of another frame.
    fn set_body(&mut self, original: &Poses, f: usize, shift_cm: Option<DVec3>) {
        if self.body_frame == Some(f) {
            return;
        }
        let mesh = shift_cm.zip(self.shape.as_ref()).and_then(|(shift_cm, shape)| {
            let mesh = shape.pose(original.frame(f), shift_cm).ok()?.mesh(BODY_SEGMENTS);
            Some(CpuMesh {
                positions: Positions::F32(
                    mesh.positions_cm.iter().map(|p| self.to_world(p.as_dvec3())).collect(),
                ),
                normals: Some(mesh.normals.iter().map(|n| self.direction_to_world(*n)).collect()),
                indices: Indices::U32(mesh.indices),
                ..Default::default()
            })
        });
        self.body_frame = Some(f);
        self.body_shown = mesh.is_some();
        if let Some(mesh) = mesh {
            self.body.geometry = Mesh::new(&self.context, &mesh);
        }
    }

    fn skeleton_instances(
        &self,
        points: &[Vec3],
        parents: &[Option<usize>],
        offset: Vec3,
    ) -> (Vec<Mat4>, Vec<Mat4>) {
        // The joints above the hips are not the body: a bone from Bandai's
        // static `joint_Root` would be a line across the room.
        let mut above_hips = vec![false; points.len()];
        for j in crate::body::feet::above_hips(parents, self.hips) {
            if let Some(above) = above_hips.get_mut(j) {
                *above = true;
            }
        }
        let joints = (0..points.len())
            .filter(|&j| !above_hips[j])
            .map(|j| ball(points[j] + offset, JOINT_RADIUS_M))
            .collect();
        let bones = parents
            .iter()
            .enumerate()
            .filter_map(|(j, parent)| {
                let p = (*parent).filter(|&p| !above_hips[p] && !above_hips[j])?;
                Some(segment(points[p] + offset, points[j] + offset, BONE_RADIUS_M))
            })
            .collect();
        (joints, bones)
    }

    pub fn orbit(&mut self, dx_px: f32, dy_px: f32) {
        self.orbit.yaw -= dx_px * 0.008;
        self.orbit.pitch = (self.orbit.pitch + dy_px * 0.008).clamp(-0.1, 1.5);
    }

    pub fn zoom(&mut self, factor: f32) {
        self.orbit.distance_m = (self.orbit.distance_m * factor.clamp(0.2, 5.0)).clamp(0.5, 200.0);
    }

    /// Moves the target in the view plane by a drag of (dx, dy) pixels.
    pub fn pan(&mut self, dx_px: f32, dy_px: f32) {
        let scale = self.orbit.distance_m * 0.0015;
        let right = vec3(self.orbit.yaw.cos(), 0.0, -self.orbit.yaw.sin());
        let forward = vec3(-self.orbit.yaw.sin(), 0.0, -self.orbit.yaw.cos());
        self.orbit.target += right * (-dx_px * scale) + forward * (dy_px * scale);
        self.follow = false;
    }

    /// Renders into the canvas (size in device pixels). A new recording,
    /// or a view of another shape, is framed anew: its paths and the body
    /// whole in view.
    pub fn render(&mut self, width: u32, height: u32) {
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        if aspect != self.framed_aspect {
            let fov = VERTICAL_FOV_DEG.to_radians();
            self.orbit.distance_m = crate::app::framing::distance_to_fit(self.framed_radius_m, fov, aspect);
            self.framed_aspect = aspect;
        }
        self.camera.set_viewport(Viewport::new_at_origo(width.max(1), height.max(1)));
        self.camera.set_view(self.orbit.position(), self.orbit.target, vec3(0.0, 1.0, 0.0));
        let lights: [&dyn Light; 2] = [&self.ambient, &self.sun];
        let target = RenderTarget::screen(&self.context, width.max(1), height.max(1));
        let Rgba(r, g, b, a) = theme::VIEW_BACKGROUND;
        let [r, g, b, a] = [r, g, b, a].map(|c| f32::from(c) / 255.0);
        target.clear(ClearState::color_and_depth(r, g, b, a, 1.0));
        // Lists of `&dyn Object` in both calls: one instance of three-d's
        // generic render code, not one per kind of object (each is kilobytes).
        let mut floor: Vec<&dyn Object> = vec![&self.grid, &self.trails];
        if self.shadow {
            floor.push(&self.shadows);
        }
        target.render(&self.camera, floor, &[]);
        let mut bodies: Vec<&dyn Object> = vec![&self.joints, &self.bones];
        if self.take.is_some() {
            bodies.push(&self.frustum);
        }
        if self.body_shown {
            bodies.push(&self.body);
        }
        if self.ghost != Ghost::Hidden {
            bodies.extend([&self.ghost_joints as &dyn Object, &self.ghost_bones]);
        }
        target.render(&self.camera, bodies, &lights);
    }
}

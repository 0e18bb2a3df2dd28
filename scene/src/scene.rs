//! The scene file (TOML, `serde`) and the loaded scene.
//!
//! Format (every section is documented in `docs/scene.md`):
//!
//! ```toml
//! [render]                      # optional, every key has a default
//! width = 128
//! height = 96
//! [camera]
//! position = [0.0, 1.0, 4.0]
//! look_at = [0.0, 1.0, 0.0]
//! fov_y = 40.0                  # degrees; up defaults to +y
//! [meshes.teapot]
//! obj = "meshes/teapot.obj"     # relative to this file
//! [meshes.ball]
//! procedural = "sphere"         # quad | box | sphere | grass
//! subdivisions = 3
//! [[instances]]
//! mesh = "teapot"
//! transform = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]  # forward 3x4 [R | T]
//! color = [0.8, 0.7, 0.6]
//! opacity = 1.0                 # below 1: translucent (hybrid renderer only)
//! [[lights]]
//! kind = "point"
//! position = [2.0, 4.0, 3.0]
//! color = [10.0, 10.0, 10.0]
//! ```
//!
//! Errors name the file and the field (`scenes/x.toml: instances[2].mesh: ...`).

use crate::mesh;
use glam::{DAffine3, DMat3, DVec3, Vec3};
use golden_model::cull::bvh::Mesh;
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::transform::exact::scene_builder_inverse;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// A scene file error: the file, the field (dotted path) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// the scene file
    pub file: PathBuf,
    /// dotted path of the offending field, e.g. `instances[2].mesh` (empty if
    /// the file as a whole is at fault)
    pub field: String,
    /// what is wrong
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}: {}", self.file.display(), self.message)
        } else {
            write!(
                f,
                "{}: field `{}`: {}",
                self.file.display(),
                self.field,
                self.message
            )
        }
    }
}

impl std::error::Error for SceneError {}

/// The largest image width or height in pixels, of the scene file's `render.width` and
/// `render.height` and of every command's `--width` and `--height` (a frame's buffers are
/// allocated up front: a larger size aborts on memory instead of rendering).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// The most shadow rays per shading point of an area light (`samples`).
pub const MAX_LIGHT_SAMPLES: u32 = 256;

/// The most AO rays per pixel (`render.ao_rays`, `--ao`): as many as an area light's
/// samples; more only lengthens the render without a visible change.
pub const MAX_AO_RAYS: u32 = 256;

/// `side` (an image width or height) if it is in `1..=MAX_IMAGE_SIDE`, else what is wrong.
fn image_side(side: u32) -> Result<u32, String> {
    if side == 0 || side > MAX_IMAGE_SIDE {
        return Err(format!("{side} is not in 1..={MAX_IMAGE_SIDE}"));
    }
    Ok(side)
}

/// `ao_rays` if it is in `0..=MAX_AO_RAYS`, else what is wrong.
pub fn ao_rays_in_range(ao_rays: u32) -> Result<u32, String> {
    if ao_rays > MAX_AO_RAYS {
        return Err(format!("{ao_rays} is not in 0..={MAX_AO_RAYS}"));
    }
    Ok(ao_rays)
}

/// A TOML array of exactly `N` elements: serde's fixed-size arrays would drop extra ones
/// silently (`position = [0, 1, 3, 99]`).
struct Exactly<T, const N: usize>([T; N]);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exactly<T, N> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<T>::deserialize(d)?;
        let len = v.len();
        v.try_into().map(Exactly).map_err(|_| {
            serde::de::Error::invalid_length(len, &format!("an array of {N} elements").as_str())
        })
    }
}

/// `deserialize_with` of a fixed-size array field ([`Exactly`]).
fn exactly<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<[T; N], D::Error> {
    Exactly::deserialize(d).map(|a| a.0)
}

/// `deserialize_with` of an optional fixed-size array field ([`Exactly`]).
fn exactly_opt<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
    d: D,
) -> Result<Option<[T; N]>, D::Error> {
    Option::<Exactly<T, N>>::deserialize(d).map(|a| a.map(|a| a.0))
}

/// `deserialize_with` of an optional 3×4 matrix ([`Exactly`] rows of exactly 4).
fn exactly_rows_opt<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<Option<[[f64; 4]; 3]>, D::Error> {
    Option::<Exactly<Exactly<f64, 4>, 3>>::deserialize(d).map(|m| m.map(|m| m.0.map(|r| r.0)))
}

/// `deserialize_with` of a list of colours ([`Exactly`] 3 channels each).
fn exactly_colors<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Vec<[f32; 3]>, D::Error> {
    Vec::<Exactly<f32, 3>>::deserialize(d).map(|v| v.into_iter().map(|c| c.0).collect())
}

fn d_width() -> u32 {
    128
}
fn d_height() -> u32 {
    128
}
fn d_ambient() -> f32 {
    0.2
}
fn d_ao_rays() -> u32 {
    4
}
fn d_ao_distance() -> f32 {
    1.0
}
fn d_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}
fn d_fov() -> f32 {
    45.0
}
fn d_color() -> [f32; 3] {
    [0.75, 0.75, 0.75]
}
fn d_samples() -> u32 {
    4
}
fn d_one() -> f32 {
    1.0
}

/// `[render]`: image size and shading constants.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RenderSettings {
    /// image width in pixels
    #[serde(default = "d_width")]
    pub width: u32,
    /// image height in pixels
    #[serde(default = "d_height")]
    pub height: u32,
    /// ambient light, scaled by the ambient-occlusion visibility
    #[serde(default = "d_ambient")]
    pub ambient: f32,
    /// ambient-occlusion rays per pixel (0: no AO rays, ambient unoccluded)
    #[serde(default = "d_ao_rays")]
    pub ao_rays: u32,
    /// AO ray length (world units)
    #[serde(default = "d_ao_distance")]
    pub ao_distance: f32,
    /// colour of pixels whose primary ray misses
    #[serde(default, deserialize_with = "exactly")]
    pub background: [f32; 3],
}

impl RenderSettings {
    /// The size of a render: `width` (the `--width` option) or the scene's, `height`
    /// (`--height`) or the scene's scaled with the width; each in `1..=MAX_IMAGE_SIDE`,
    /// else an error naming the option.
    pub fn image_size(
        &self,
        width: Option<u32>,
        height: Option<u32>,
    ) -> Result<(u32, u32), String> {
        let w = image_side(width.unwrap_or(self.width)).map_err(|e| format!("--width {e}"))?;
        let h = match height {
            Some(h) => image_side(h).map_err(|e| format!("--height {e}"))?,
            None => {
                let scaled = (self.height as u64 * w as u64 / self.width as u64).max(1);
                image_side(u32::try_from(scaled).unwrap_or(u32::MAX))
                    .map_err(|e| format!("the height scaled to --width {w}: {e} (give --height)"))?
            }
        };
        Ok((w, h))
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: d_width(),
            height: d_height(),
            ambient: d_ambient(),
            ao_rays: d_ao_rays(),
            ao_distance: d_ao_distance(),
            background: [0.0; 3],
        }
    }
}

/// `[camera]`: a pinhole camera.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// eye position
    #[serde(deserialize_with = "exactly")]
    pub position: [f32; 3],
    /// point the camera looks at
    #[serde(deserialize_with = "exactly")]
    pub look_at: [f32; 3],
    /// up vector (default +y)
    #[serde(default = "d_up", deserialize_with = "exactly")]
    pub up: [f32; 3],
    /// vertical field of view in degrees
    #[serde(default = "d_fov")]
    pub fov_y: f32,
}

/// `[meshes.NAME]`: an OBJ file or a procedural shape.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshDef {
    obj: Option<String>,
    procedural: Option<String>,
    subdivisions: Option<u32>,
    blades: Option<u32>,
    segments: Option<u32>,
    height: Option<f32>,
    width: Option<f32>,
    size: Option<f32>,
    seed: Option<u64>,
    /// move the mesh so that its box is centred on x = z = 0 with its bottom at y = 0
    #[serde(default)]
    recenter: bool,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct InstanceDef {
    mesh: String,
    #[serde(default, deserialize_with = "exactly_rows_opt")]
    transform: Option<[[f64; 4]; 3]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    translate: Option<[f64; 3]>,
    /// axis (3) and angle in degrees
    #[serde(default, deserialize_with = "exactly_opt")]
    rotate: Option<[f64; 4]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    scale: Option<[f64; 3]>,
    #[serde(default = "d_color", deserialize_with = "exactly")]
    color: [f32; 3],
    /// 1 (default): opaque; below 1: translucent (the hybrid renderer blends it)
    #[serde(default = "d_one")]
    opacity: f32,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct GridDef {
    mesh: String,
    #[serde(deserialize_with = "exactly")]
    count: [u32; 2],
    spacing: f64,
    #[serde(default, deserialize_with = "exactly")]
    origin: [f64; 3],
    #[serde(default = "d_one")]
    scale: f32,
    #[serde(default)]
    seed: u64,
    #[serde(default, deserialize_with = "exactly_colors")]
    colors: Vec<[f32; 3]>,
}

/// `[[lights]]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(try_from = "LightDef")]
pub enum Light {
    /// A point light: radiant intensity `color` (falls off with 1/r²).
    Point {
        /// position
        position: [f32; 3],
        /// intensity per channel
        color: [f32; 3],
    },
    /// A parallelogram `corner + u·edge_u + v·edge_v`, `u, v ∈ [0,1]`, emitting
    /// `color` (radiance) on the side `edge_u × edge_v` points to; `samples`
    /// shadow rays per shading point.
    Area {
        /// one corner
        corner: [f32; 3],
        /// first edge
        edge_u: [f32; 3],
        /// second edge
        edge_v: [f32; 3],
        /// emitted radiance per channel
        color: [f32; 3],
        /// shadow rays per shading point
        samples: u32,
    },
}

/// A `[[lights]]` table as written: one struct for both kinds, so that an error in
/// a value names its key (serde's internally tagged enums keep no field spans);
/// [`Light`]'s `TryFrom` then asks each kind for its own keys.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDef {
    kind: LightKind,
    #[serde(default, deserialize_with = "exactly_opt")]
    position: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    corner: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    edge_u: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    edge_v: Option<[f32; 3]>,
    #[serde(default, deserialize_with = "exactly_opt")]
    color: Option<[f32; 3]>,
    samples: Option<u32>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum LightKind {
    Point,
    Area,
}

impl TryFrom<LightDef> for Light {
    type Error = String;

    fn try_from(l: LightDef) -> Result<Light, String> {
        let (kind, keys) = match l.kind {
            LightKind::Point => ("point", "`position`, `color`"),
            LightKind::Area => ("area", "`corner`, `edge_u`, `edge_v`, `color`, `samples`"),
        };
        let need = |v: Option<[f32; 3]>, key: &str| {
            v.ok_or_else(|| format!("missing field `{key}` (a {kind} light takes {keys})"))
        };
        let refuse = |given: bool, key: &str| match given {
            true => Err(format!(
                "field `{key}` is not a {kind} light's (it takes {keys})"
            )),
            false => Ok(()),
        };
        match l.kind {
            LightKind::Point => {
                refuse(l.corner.is_some(), "corner")?;
                refuse(l.edge_u.is_some(), "edge_u")?;
                refuse(l.edge_v.is_some(), "edge_v")?;
                refuse(l.samples.is_some(), "samples")?;
                Ok(Light::Point {
                    position: need(l.position, "position")?,
                    color: need(l.color, "color")?,
                })
            }
            LightKind::Area => {
                refuse(l.position.is_some(), "position")?;
                Ok(Light::Area {
                    corner: need(l.corner, "corner")?,
                    edge_u: need(l.edge_u, "edge_u")?,
                    edge_v: need(l.edge_v, "edge_v")?,
                    color: need(l.color, "color")?,
                    samples: l.samples.unwrap_or_else(d_samples),
                })
            }
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneDef {
    #[serde(default)]
    render: RenderSettings,
    camera: Camera,
    meshes: BTreeMap<String, MeshDef>,
    #[serde(default)]
    instances: Vec<InstanceDef>,
    #[serde(default)]
    grids: Vec<GridDef>,
    #[serde(default)]
    lights: Vec<Light>,
}

/// One placed mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// index into [`Scene::meshes`]
    pub mesh: usize,
    /// forward (model-to-world) transform `[R | T]`, rows, in f32 (the unit's format)
    pub transform: [[f32; 4]; 3],
    /// diffuse albedo
    pub color: [f32; 3],
    /// opacity in `(0, 1]`: below 1 the surface is translucent, which only the
    /// hybrid renderer models (`docs/scene.md` §5); ray-traced visibility
    /// treats every surface as opaque
    pub opacity: f32,
}

impl Instance {
    /// The surface is translucent (opacity below 1).
    pub fn translucent(&self) -> bool {
        self.opacity < 1.0
    }
}

/// A loaded scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// the scene file
    pub path: PathBuf,
    /// image and shading settings
    pub render: RenderSettings,
    /// camera
    pub camera: Camera,
    /// meshes with their names (the TOML table keys, sorted)
    pub meshes: Vec<(String, Mesh)>,
    /// instances (explicit ones first, then the grids expanded)
    pub instances: Vec<Instance>,
    /// lights
    pub lights: Vec<Light>,
}

fn err(file: &Path, field: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError {
        file: file.to_path_buf(),
        field: field.into(),
        message: message.into(),
    }
}

/// Field path of a `toml` deserialisation error, from its span in the source.
fn field_of_span(text: &str, span: std::ops::Range<usize>) -> String {
    // The key path is reconstructed from the table headers and the key on the
    // line of the span (good enough for error messages; exact for this format).
    // through the end of the span's line: a span at a `[[lights]]` header (a light's own
    // error, a key its kind misses or does not take: no key has the span) belongs to that
    // table
    let start = span.start.min(text.len());
    let upto = &text[..text[start..].find('\n').map_or(text.len(), |n| start + n)];
    let mut table = String::new();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for line in upto.lines() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix("[[").and_then(|s| s.split("]]").next()) {
            let n = counts.entry(h.trim().to_string()).or_insert(0);
            table = format!("{}[{}]", h.trim(), n);
            *n += 1;
        } else if let Some(h) = l.strip_prefix('[').and_then(|s| s.split(']').next()) {
            table = h.trim().to_string();
        }
    }
    let line = text[..span.start.min(text.len())]
        .rsplit('\n')
        .next()
        .unwrap_or("")
        .to_string()
        + text[span.start.min(text.len())..]
            .split('\n')
            .next()
            .unwrap_or("");
    let key = line
        .split('=')
        .next()
        .filter(|_| line.contains('='))
        .map(|k| k.trim().to_string())
        .unwrap_or_default();
    match (table.is_empty(), key.is_empty()) {
        (true, _) => key,
        (false, true) => table,
        (false, false) => format!("{table}.{key}"),
    }
}

/// The section whose own deserialisation fails (for errors without a span,
/// such as a missing field).
fn locate_section(text: &str) -> Option<String> {
    let t: toml::Table = toml::from_str(text).ok()?;
    fn fails<T: serde::de::DeserializeOwned>(v: &toml::Value) -> bool {
        T::deserialize(v.clone()).is_err()
    }
    for (k, v) in &t {
        let bad = match k.as_str() {
            "render" => fails::<RenderSettings>(v),
            "camera" => fails::<Camera>(v),
            "meshes" => fails::<BTreeMap<String, MeshDef>>(v),
            "instances" | "grids" | "lights" => {
                if let Some(a) = v.as_array() {
                    for (i, x) in a.iter().enumerate() {
                        let b = match k.as_str() {
                            "instances" => fails::<InstanceDef>(x),
                            "grids" => fails::<GridDef>(x),
                            _ => fails::<Light>(x),
                        };
                        if b {
                            return Some(format!("{k}[{i}]"));
                        }
                    }
                }
                false
            }
            _ => false,
        };
        if bad {
            return Some(k.clone());
        }
    }
    None
}

impl Scene {
    /// Reads and checks a scene file; paths inside are relative to its folder.
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| err(path, "", format!("cannot read: {e}")))?;
        Scene::parse(&text, path)
    }

    /// Parses scene text as if it were the file `path`.
    pub fn parse(text: &str, path: &Path) -> Result<Scene, SceneError> {
        let def: SceneDef = toml::from_str(text).map_err(|e| {
            // a span at an array element's header, not at a key (a light's own error):
            // toml may point at the first element, so the failing one is searched for
            let field = e
                .span()
                .map(|s| field_of_span(text, s))
                .filter(|f| !f.is_empty() && !f.ends_with(']'))
                .or_else(|| locate_section(text))
                .unwrap_or_default();
            err(path, field, e.message().to_string())
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        let r = &def.render;
        image_side(r.width).map_err(|e| err(path, "render.width", e))?;
        image_side(r.height).map_err(|e| err(path, "render.height", e))?;
        ao_rays_in_range(r.ao_rays).map_err(|e| err(path, "render.ao_rays", e))?;
        if !(r.ao_distance > 0.0 && r.ao_distance.is_finite()) {
            return Err(err(path, "render.ao_distance", "must be positive"));
        }
        if !(r.ambient >= 0.0 && r.ambient.is_finite()) {
            return Err(err(
                path,
                "render.ambient",
                format!("{}: must be finite and not negative", r.ambient),
            ));
        }
        check_color(path, "render.background", r.background)?;
        let c = &def.camera;
        if !(c.fov_y > 0.0 && c.fov_y < 180.0) {
            return Err(err(path, "camera.fov_y", "must be in (0, 180) degrees"));
        }
        if c.position == c.look_at {
            return Err(err(path, "camera.look_at", "equals camera.position"));
        }
        for (field, v) in [
            ("camera.position", c.position),
            ("camera.look_at", c.look_at),
            ("camera.up", c.up),
        ] {
            check_point(path, field, v)?;
        }
        // the camera basis is built in f32 (render::Cam): its squared length must not overflow
        let (eye, at) = (Vec3::from(c.position), Vec3::from(c.look_at));
        let len2 = (at - eye).length_squared();
        if !len2.is_finite() || len2 == 0.0 {
            let dist = at.as_dvec3().distance(eye.as_dvec3());
            return Err(err(
                path,
                "camera.look_at",
                format!(
                    "is {dist:.3e} from camera.position: the camera set-up (binary32) needs a distance between about 1e-19 and 1.8e19"
                ),
            ));
        }
        // a zero `up`, or one along the view direction, leaves no camera basis (NaN rays)
        let (_, right, up) = crate::render::camera_basis(c);
        if !(right.is_finite() && up.is_finite() && up.length() > 0.0) {
            return Err(err(
                path,
                "camera.up",
                format!(
                    "{:?}: must not be zero nor parallel to look_at − position",
                    c.up
                ),
            ));
        }
        let mut meshes = Vec::new();
        let mut names = BTreeMap::new();
        for (name, m) in &def.meshes {
            let field = format!("meshes.{name}");
            let mut mesh = build_mesh(path, dir, &field, m)?;
            if m.recenter {
                let (lo, hi) = mesh.bounds();
                let c = Vec3::new((lo[0] + hi[0]) / 2.0, lo[1], (lo[2] + hi[2]) / 2.0);
                for v in &mut mesh.vertices {
                    *v = (Vec3::from(*v) - c).to_array();
                }
            }
            // obj meshes are checked as loaded (naming the file); this also
            // covers procedural shapes and recentering (finite but huge values)
            mesh.check_finite()
                .map_err(|e| err(path, &field, format!("mesh `{name}`: {e}")))?;
            names.insert(name.clone(), meshes.len());
            meshes.push((name.clone(), mesh));
        }
        let mut instances = Vec::new();
        for (i, inst) in def.instances.iter().enumerate() {
            let field = format!("instances[{i}]");
            let mesh = *names.get(&inst.mesh).ok_or_else(|| {
                err(
                    path,
                    format!("{field}.mesh"),
                    format!("no mesh named `{}` in [meshes]", inst.mesh),
                )
            })?;
            let transform = instance_transform(path, &field, inst)?;
            check_color(path, format!("{field}.color"), inst.color)?;
            if !(inst.opacity > 0.0 && inst.opacity <= 1.0) {
                return Err(err(
                    path,
                    format!("{field}.opacity"),
                    format!("{} is not in (0, 1]", inst.opacity),
                ));
            }
            instances.push(Instance {
                mesh,
                transform,
                color: inst.color,
                opacity: inst.opacity,
            });
        }
        for (g, grid) in def.grids.iter().enumerate() {
            let field = format!("grids[{g}]");
            let mesh = *names.get(&grid.mesh).ok_or_else(|| {
                err(
                    path,
                    format!("{field}.mesh"),
                    format!("no mesh named `{}` in [meshes]", grid.mesh),
                )
            })?;
            // in u64: the product of two u32 counts does not wrap
            let count = grid.count[0] as u64 * grid.count[1] as u64;
            if !(1..=1_000_000).contains(&count) {
                return Err(err(
                    path,
                    format!("{field}.count"),
                    format!("{:?}: need 1..=1e6 instances", grid.count),
                ));
            }
            if !grid.spacing.is_finite() {
                return Err(err(path, format!("{field}.spacing"), "must be finite"));
            }
            check_point(path, format!("{field}.origin"), grid.origin)?;
            if !(grid.scale > 0.0 && grid.scale.is_finite()) {
                return Err(err(
                    path,
                    format!("{field}.scale"),
                    "must be positive and finite",
                ));
            }
            for (k, &c) in grid.colors.iter().enumerate() {
                check_color(path, format!("{field}.colors[{k}]"), c)?;
            }
            for ix in 0..grid.count[0] {
                for iz in 0..grid.count[1] {
                    let k = (ix as u64) << 32 | iz as u64;
                    let yaw = 2.0 * std::f64::consts::PI * mesh::unit(grid.seed, k);
                    let s = grid.scale as f64 * (0.8 + 0.4 * mesh::unit(grid.seed ^ 1, k));
                    let (sn, cs) = yaw.sin_cos();
                    let t = [
                        grid.origin[0] + ix as f64 * grid.spacing,
                        grid.origin[1],
                        grid.origin[2] + iz as f64 * grid.spacing,
                    ];
                    let m = [
                        [cs * s, 0.0, sn * s, t[0]],
                        [0.0, s, 0.0, t[1]],
                        [-sn * s, 0.0, cs * s, t[2]],
                    ];
                    let color = if grid.colors.is_empty() {
                        d_color()
                    } else {
                        grid.colors[(ix as usize * 7 + iz as usize * 3) % grid.colors.len()]
                    };
                    let transform =
                        checked_transform(path, &format!("{field} (instance x {ix}, z {iz})"), m)?;
                    instances.push(Instance {
                        mesh,
                        transform,
                        color,
                        opacity: 1.0,
                    });
                }
            }
        }
        if instances.is_empty() {
            return Err(err(path, "instances", "the scene places no instance"));
        }
        for (i, l) in def.lights.iter().enumerate() {
            check_light(path, &format!("lights[{i}]"), l)?;
        }
        Ok(Scene {
            path: path.to_path_buf(),
            render: def.render,
            camera: def.camera,
            meshes,
            instances,
            lights: def.lights,
        })
    }

    /// Total triangles over all instances.
    pub fn instanced_triangles(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.meshes[i.mesh].1.triangles.len())
            .sum()
    }
}

/// The most quads per grass blade (`segments`).
pub const MAX_GRASS_SEGMENTS: u32 = 1024;

/// The most quads of a grass mesh (`blades × segments`, two triangles each): as many as
/// the most blades (2e6) at the default 4 segments.
pub const MAX_GRASS_QUADS: u64 = 8_000_000;

fn build_mesh(file: &Path, dir: &Path, field: &str, m: &MeshDef) -> Result<Mesh, SceneError> {
    // a parameter of another shape would be ignored silently
    let grass_only = [
        ("blades", m.blades.is_some()),
        ("segments", m.segments.is_some()),
        ("height", m.height.is_some()),
        ("width", m.width.is_some()),
        ("size", m.size.is_some()),
        ("seed", m.seed.is_some()),
    ];
    let shape = m.procedural.as_deref();
    for (name, given) in grass_only {
        if given && shape != Some("grass") {
            return Err(err(
                file,
                format!("{field}.{name}"),
                "only `procedural = \"grass\"` takes it",
            ));
        }
    }
    if m.subdivisions.is_some() && shape != Some("sphere") {
        return Err(err(
            file,
            format!("{field}.subdivisions"),
            "only `procedural = \"sphere\"` takes it",
        ));
    }
    match (&m.obj, &m.procedural) {
        (Some(_), Some(_)) => Err(err(
            file,
            field,
            "give either `obj` or `procedural`, not both",
        )),
        (None, None) => Err(err(file, field, "needs `obj` or `procedural`")),
        (Some(obj), None) => {
            let p = dir.join(obj);
            mesh::load_obj(&p).map_err(|e| {
                err(
                    file,
                    format!("{field}.obj"),
                    format!("{}: {e}", p.display()),
                )
            })
        }
        (None, Some(kind)) => match kind.as_str() {
            "quad" => Ok(mesh::quad()),
            "box" => Ok(mesh::cube()),
            "sphere" => {
                let s = m.subdivisions.unwrap_or(2);
                if s > 7 {
                    return Err(err(file, format!("{field}.subdivisions"), "at most 7"));
                }
                Ok(mesh::icosphere(s))
            }
            "grass" => {
                let blades = m.blades.unwrap_or(1000);
                if blades == 0 || blades > 2_000_000 {
                    return Err(err(file, format!("{field}.blades"), "must be in 1..=2e6"));
                }
                let segments = m.segments.unwrap_or(4);
                if segments == 0 || segments > MAX_GRASS_SEGMENTS {
                    return Err(err(
                        file,
                        format!("{field}.segments"),
                        format!("{segments} is not in 1..={MAX_GRASS_SEGMENTS}"),
                    ));
                }
                let quads = blades as u64 * segments as u64;
                if quads > MAX_GRASS_QUADS {
                    return Err(err(
                        file,
                        format!("{field}.segments"),
                        format!("blades × segments = {quads}: at most {MAX_GRASS_QUADS} quads"),
                    ));
                }
                let (height, width, size) = (
                    m.height.unwrap_or(1.0),
                    m.width.unwrap_or(0.02),
                    m.size.unwrap_or(1.0),
                );
                for (name, v, least) in [("height", height, 0.0), ("width", width, 0.0)] {
                    if !(v > least && v.is_finite()) {
                        return Err(err(
                            file,
                            format!("{field}.{name}"),
                            format!("{v}: must be positive and finite"),
                        ));
                    }
                }
                if !(size >= 0.0 && size.is_finite()) {
                    return Err(err(
                        file,
                        format!("{field}.size"),
                        format!("{size}: must be finite and not negative"),
                    ));
                }
                Ok(mesh::grass(
                    blades,
                    segments,
                    height,
                    width,
                    size,
                    m.seed.unwrap_or(1),
                ))
            }
            other => Err(err(
                file,
                format!("{field}.procedural"),
                format!("unknown shape `{other}` (quad, box, sphere, grass)"),
            )),
        },
    }
}

/// The forward transform `[R | T]` of an instance's binary32 rows
/// ([`Instance::transform`]) in f64 (exact: every entry is a binary32 value).
pub(crate) fn forward_affine(f: &[[f32; 4]; 3]) -> DAffine3 {
    let col = |j: usize| DVec3::new(f[0][j] as f64, f[1][j] as f64, f[2][j] as f64);
    DAffine3::from_cols(col(0), col(1), col(2), col(3))
}

/// A point or a vector (a position, an edge, a direction) must have finite coordinates.
fn check_point<T: Copy + Into<f64> + std::fmt::Debug>(
    file: &Path,
    field: impl Into<String>,
    v: [T; 3],
) -> Result<(), SceneError> {
    if v.iter().all(|&x| x.into().is_finite()) {
        Ok(())
    } else {
        Err(err(
            file,
            field,
            format!("{v:?}: coordinates must be finite"),
        ))
    }
}

/// A colour, intensity or radiance must be finite and not negative.
fn check_color(file: &Path, field: impl Into<String>, c: [f32; 3]) -> Result<(), SceneError> {
    if c.iter().all(|x| *x >= 0.0 && x.is_finite()) {
        return Ok(());
    }
    Err(err(
        file,
        field,
        format!("{c:?}: channels must be finite and not negative"),
    ))
}

/// A light's points finite, its colour a colour, an area light's edges spanning an area,
/// its samples in `1..=MAX_LIGHT_SAMPLES`.
fn check_light(file: &Path, field: &str, light: &Light) -> Result<(), SceneError> {
    let finite = |name: &str, v: [f32; 3]| check_point(file, format!("{field}.{name}"), v);
    match light {
        Light::Point { position, color } => {
            finite("position", *position)?;
            check_color(file, format!("{field}.color"), *color)
        }
        Light::Area {
            corner,
            edge_u,
            edge_v,
            color,
            samples,
        } => {
            finite("corner", *corner)?;
            finite("edge_u", *edge_u)?;
            finite("edge_v", *edge_v)?;
            // the emitting side and the sample density come from edge_u × edge_v
            let n = Vec3::from(*edge_u).cross(Vec3::from(*edge_v));
            if !(n.is_finite() && n.length_squared() > 0.0) {
                return Err(err(
                    file,
                    format!("{field}.edge_v"),
                    format!("{edge_u:?} × {edge_v:?}: the edges must span a finite, nonzero area"),
                ));
            }
            check_color(file, format!("{field}.color"), *color)?;
            if *samples == 0 || *samples > MAX_LIGHT_SAMPLES {
                return Err(err(
                    file,
                    format!("{field}.samples"),
                    format!("{samples} is not in 1..={MAX_LIGHT_SAMPLES}"),
                ));
            }
            Ok(())
        }
    }
}

/// `R⁻¹` of an instance's binary32 rows ([`Instance::transform`]) as the scene builder
/// stores it: row-major binary32 bits, the exact inverse rounded once
/// (`scene_builder_inverse`, the transform unit's `inverse=pre`).
pub(crate) fn builder_inverse(f: &[[f32; 4]; 3]) -> [u64; 9] {
    let r_bits: [u64; 9] = std::array::from_fn(|k| f[k / 3][k % 3].to_bits() as u64);
    scene_builder_inverse(FloatFormat::BINARY32, RoundingMode::NearestEven, &r_bits)
}

/// `R = Rot(axis, angle)·diag(scale)`, `T = translate`, or the explicit 3×4.
fn instance_transform(
    file: &Path,
    field: &str,
    inst: &InstanceDef,
) -> Result<[[f32; 4]; 3], SceneError> {
    let m: [[f64; 4]; 3] = if let Some(t) = inst.transform {
        if inst.translate.is_some() || inst.rotate.is_some() || inst.scale.is_some() {
            return Err(err(
                file,
                format!("{field}.transform"),
                "give either `transform` or translate/rotate/scale, not both",
            ));
        }
        t
    } else {
        let s = DVec3::from(inst.scale.unwrap_or([1.0; 3]));
        let [ax, ay, az, deg] = inst.rotate.unwrap_or([0.0, 1.0, 0.0, 0.0]);
        let axis = DVec3::new(ax, ay, az);
        let l = axis.length();
        if l == 0.0 || !l.is_finite() {
            return Err(err(file, format!("{field}.rotate"), "axis must be nonzero"));
        }
        // divided, not glam's normalize (a reciprocal): the same f32 entries as before
        let rot = DMat3::from_axis_angle(axis / l, deg.to_radians());
        let rs = DMat3::from_cols(rot.x_axis * s.x, rot.y_axis * s.y, rot.z_axis * s.z);
        let t = inst.translate.unwrap_or([0.0; 3]);
        [0, 1, 2].map(|i| rs.row(i).extend(t[i]).to_array())
    };
    checked_transform(file, &format!("{field}.transform"), m)
}

/// The binary32 rows of a forward instance transform `[R | T]` (of `[[instances]]` and of
/// every instance of `[[grids]]`), if the scene builder can use them: finite entries, `R`
/// not singular and its inverse, as the builder stores it (`scene_builder_inverse`, each
/// entry rounded once), finite in binary32 (else the instance silently vanishes).
fn checked_transform(
    file: &Path,
    field: &str,
    m: [[f64; 4]; 3],
) -> Result<[[f32; 4]; 3], SceneError> {
    let f = m.map(|row| row.map(|x| x as f32));
    if f.iter().flatten().any(|x| !x.is_finite()) {
        return Err(err(file, field, "entries must be finite f32"));
    }
    // expanded along the first row, as the singularity check always was
    let det = forward_affine(&f).matrix3.transpose().determinant();
    if det == 0.0 || !det.is_finite() {
        return Err(err(file, field, "the linear part is singular"));
    }
    if builder_inverse(&f)
        .iter()
        .any(|&b| !f32::from_bits(b as u32).is_finite())
    {
        return Err(err(
            file,
            field,
            "the inverse of the linear part overflows binary32 (a scale too small)",
        ));
    }
    Ok(f)
}

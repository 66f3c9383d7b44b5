//! Scene specialisation: compiling a graph against what one scene can show
//! (docs/specialise.md).
//!
//! [`specialise`] takes a graph and a [`SceneInfo`] (what the renderer or app knows: time
//! fixed or animated, the lights, a constant environment or not, the light's coherence
//! length) and returns a new graph, with every rewrite listed as a [`Rewrite`]:
//!
//! - **exact rewrites**: the `time` attribute folded at a fixed time; the `light` direction
//!   (and `light_color` where nothing casts shadows) folded when the scene has one
//!   directional light; `scene:environment` lookups replaced by the environment's radiance
//!   when it is the same in every direction; then every node whose inputs are all constant
//!   evaluated once by the CPU plan and replaced by its value; then the nodes that reach no
//!   output removed. These change no value (the folds run the same kernels as the
//!   executor), so the specialised render equals the full one up to float rounding of
//!   values the GPU computes differently.
//! - **approximations** (only with [`SpecialiseOptions::approximate`]): a free thin film
//!   whose optical path difference exceeds the light's coherence length everywhere in its
//!   domain replaced by its incoherent limit ([`thin_film`]), with the error measured in
//!   `tests/graphs/specialise.rs` and stated in docs/specialise.md.
//!
//! The core does no I/O: the result is a [`GraphDocument`] and its validated [`Graph`].

mod fold;
pub mod thin_film;

use crate::document::GraphDocument;
use crate::error::GraphError;
use crate::graph::Graph;
use crate::plan::EvalError;
use crate::registry::Registry;
use crate::scene::{Environment, Light, Scene};
use std::fmt;

/// A light as the specialiser sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightInfo {
    /// Parallel light: the same unit direction (towards the light) and radiance everywhere.
    Directional {
        /// Unit direction towards the light.
        direction: [f32; 3],
        /// `color · intensity`.
        radiance: [f32; 3],
    },
    /// A light whose direction and falloff vary over the surface.
    Local,
}

/// The environment as the specialiser sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EnvironmentInfo {
    /// Radiance varies with direction (a sky with a gradient or a sun, an image).
    Varying,
    /// The same radiance in every direction (black: no environment).
    Constant([f32; 3]),
}

/// What a scene fixes for the material: the inputs the specialiser may treat as constant.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneInfo {
    /// The time of the frame, or `None` when it is animated.
    pub time: Option<f32>,
    /// The lights, in order.
    pub lights: Vec<LightInfo>,
    /// Whether anything besides the material surface casts shadows (then `light_color`
    /// varies over the surface even for a directional light).
    pub shadow_casters: bool,
    /// The environment.
    pub environment: EnvironmentInfo,
    /// Coherence length of the light in nm (see [`thin_film::COHERENCE_LENGTH_D65_NM`]).
    pub coherence_length_nm: f32,
}

impl SceneInfo {
    /// What `scene` fixes, at `time` (`None`: the time is animated, e.g. `render --frames`).
    pub fn of(scene: &Scene, time: Option<f32>) -> SceneInfo {
        let lights = scene
            .lights
            .iter()
            .map(|l| match l {
                Light::Directional(_) => {
                    let (d, c, _) = l.incident(glam::Vec3::ZERO);
                    LightInfo::Directional {
                        direction: d.to_array(),
                        radiance: c.to_array(),
                    }
                }
                Light::Point(_) => LightInfo::Local,
            })
            .collect();
        SceneInfo {
            time,
            lights,
            shadow_casters: !scene.geometry().casters.is_empty(),
            environment: environment_info(&scene.environment),
            coherence_length_nm: thin_film::COHERENCE_LENGTH_D65_NM,
        }
    }

    /// A scene that fixes nothing: animated time, one local light, a varying environment.
    pub fn nothing_fixed() -> SceneInfo {
        SceneInfo {
            time: None,
            lights: vec![LightInfo::Local],
            shadow_casters: true,
            environment: EnvironmentInfo::Varying,
            coherence_length_nm: f32::INFINITY,
        }
    }

    /// The one directional light, when the scene has exactly one light and it is directional.
    pub fn single_directional(&self) -> Option<([f32; 3], [f32; 3])> {
        match self.lights.as_slice() {
            [
                LightInfo::Directional {
                    direction,
                    radiance,
                },
            ] => Some((*direction, *radiance)),
            _ => None,
        }
    }
}

/// Whether an environment's radiance is the same in every direction: a sky whose zenith,
/// horizon and ground colours are equal, with no visible sun disc or halo.
fn environment_info(env: &Environment) -> EnvironmentInfo {
    match env {
        Environment::Sky(s) => {
            let no_sun = s.sun_color == [0.0; 3] || (s.sun_intensity == 0.0 && s.halo == 0.0);
            if s.zenith_color == s.horizon_color && s.horizon_color == s.ground_color && no_sun {
                EnvironmentInfo::Constant(s.zenith_color)
            } else {
                EnvironmentInfo::Varying
            }
        }
        Environment::Image(_) => EnvironmentInfo::Varying,
    }
}

/// How far [`specialise`] may go.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpecialiseOptions {
    /// Treat the parameters as constants at these values (the file's for parameters not
    /// named) and fold them; the result exposes no parameters.
    pub bake_parameters: Option<Vec<(String, crate::value::Value)>>,
    /// Also apply the threshold rewrites (documented approximations).
    pub approximate: bool,
}

/// The kind of one rewrite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RewriteKind {
    /// The `time` attribute replaced by the frame's time.
    Time,
    /// The `light` attribute replaced by the one directional light's direction.
    LightDirection,
    /// The `light_color` attribute replaced by the one directional light's radiance.
    LightColor,
    /// A `scene:environment` lookup replaced by the constant environment's radiance.
    Environment,
    /// A parameter fixed at its value.
    Parameter,
    /// A node whose inputs are all constant evaluated once and replaced by its value.
    Fold,
    /// A node that reaches no output removed.
    Dead,
    /// A thin film replaced by its incoherent limit (an approximation).
    IncoherentFilm,
}

impl RewriteKind {
    /// A short name for listings.
    pub const fn name(self) -> &'static str {
        match self {
            RewriteKind::Time => "time",
            RewriteKind::LightDirection => "light",
            RewriteKind::LightColor => "light_color",
            RewriteKind::Environment => "environment",
            RewriteKind::Parameter => "parameter",
            RewriteKind::Fold => "fold",
            RewriteKind::Dead => "dead",
            RewriteKind::IncoherentFilm => "incoherent_film",
        }
    }
    /// Whether the rewrite changes values only by float rounding.
    pub const fn is_exact(self) -> bool {
        !matches!(self, RewriteKind::IncoherentFilm)
    }
}

/// One rewrite: which node, what was done, why.
#[derive(Clone, Debug, PartialEq)]
pub struct Rewrite {
    /// The node's id in the input graph.
    pub node: String,
    /// What was done.
    pub kind: RewriteKind,
    /// Why, with the values used.
    pub reason: String,
}

impl fmt::Display for Rewrite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} [{}]: {}", self.node, self.kind.name(), self.reason)
    }
}

/// A specialised graph and what was done to get it.
#[derive(Clone, Debug)]
pub struct Specialised {
    /// The specialised graph, validated.
    pub graph: Graph,
    /// Its document (variants resolved, switches gone).
    pub document: GraphDocument,
    /// The rewrites, in the order they were made.
    pub rewrites: Vec<Rewrite>,
}

impl Specialised {
    /// The rewrites, one line each, for the command line.
    pub fn listing(&self) -> String {
        let mut s = format!(
            "specialised '{}': {} rewrites, {} nodes\n",
            self.graph.name,
            self.rewrites.len(),
            self.graph.nodes().len()
        );
        for r in &self.rewrites {
            s += &format!("  {r}\n");
        }
        s
    }
    /// Whether every rewrite is exact.
    pub fn is_exact(&self) -> bool {
        self.rewrites.iter().all(|r| r.kind.is_exact())
    }
}

/// Errors of [`specialise`], naming the graph.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpecialiseError {
    /// A rewritten document failed to validate (a bug of the specialiser: report it).
    #[error("graph '{graph}': the specialised document does not validate: {}", first(.errors))]
    Invalid {
        /// The graph's name.
        graph: String,
        /// The validation errors.
        errors: Vec<GraphError>,
    },
    /// Compiling the plan that folds constants failed.
    #[error("graph '{graph}': {error}")]
    Eval {
        /// The graph's name.
        graph: String,
        /// The plan's error (boxed: it is large, and every `Result` of the specialiser would carry its size).
        error: Box<EvalError>,
    },
}

fn first(errors: &[GraphError]) -> String {
    errors.first().map(|e| e.to_string()).unwrap_or_default()
}

/// Specialises `graph` for `scene` at `time` (`None`: animated), keeping its parameters;
/// with `approximate`, the threshold rewrites too.
pub fn for_scene(
    graph: &Graph,
    scene: &Scene,
    time: Option<f32>,
    approximate: bool,
) -> Result<Specialised, SpecialiseError> {
    specialise(
        graph,
        Registry::builtin(),
        &SceneInfo::of(scene, time),
        &SpecialiseOptions {
            bake_parameters: None,
            approximate,
        },
    )
}

/// Specialises `graph` (at its current variant choices) for `scene`: see the module docs.
pub fn specialise(
    graph: &Graph,
    registry: &Registry,
    scene: &SceneInfo,
    options: &SpecialiseOptions,
) -> Result<Specialised, SpecialiseError> {
    fold::Specialiser::new(graph, registry, scene, options)?.run()
}

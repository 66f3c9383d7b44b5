//! The stages a case runs, each the code users hit: graphs load (with their group files
//! from memory), save and reload to the same bytes, plan, evaluate, compile to WGSL that
//! naga accepts (compute and fragment) and give the app contract of the render module;
//! scenes parse, validate, save and reload to the same bytes, reserve their meshes in a
//! small memory budget and build them (a tiny frame now and then); `--set` overrides are
//! parsed, applied, planned and evaluated through `matgraph::overrides`.

use super::cases::{Case, Family};
use super::files::MemFiles;
use matgraph::budget::MemoryBudget;
use matgraph::exec::SampleBatch;
use matgraph::material::{Material, MaterialError, MaterialOptions};
use matgraph::node::Attribute;
use matgraph::overrides;
use matgraph::plan::{Plan, PlanOptions};
use matgraph::scene::Scene;
use matgraph::wgsl::{Entry, ShaderError, WgslOptions, generate};
use matgraph::{Graph, GraphDocument, Registry};
use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, OnceLock};

/// The memory budget of a scene case's meshes: the fixed meshes' 16 MiB and 16 MiB for the
/// material's surface (the default ball's 33 153 vertices take 14.1 MiB), so that a case
/// builds at most ~45 000 vertices and larger scenes are refused by the budget.
pub const SCENE_BUDGET: u64 = 32 << 20;

/// What went wrong in one case.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    /// The stage: `load`, `save`, `plan`, `eval`, `wgsl`, `contract`, `scene`, `set`.
    pub stage: &'static str,
    /// A panic's message or the failed property.
    pub message: String,
}

/// The outcome of one case.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outcome {
    /// A finding, if any.
    pub finding: Option<Finding>,
    /// The known signature it matched instead, if any.
    pub known: Option<&'static str>,
}

/// Why a stage stopped: a finding or a known signature.
enum Stop {
    Finding(String),
}

impl From<String> for Stop {
    fn from(s: String) -> Stop {
        Stop::Finding(s)
    }
}

/// Runs every stage of `case`, panics caught.
pub fn run_case(case: &Case) -> Outcome {
    let stage = Cell::new("load");
    let result = catch_unwind(AssertUnwindSafe(|| match case.family {
        Family::Graph | Family::Grouped => graph_stages(case, &stage),
        Family::Scene => scene_stages(&case.text, &stage),
        Family::Set => set_stages(case, &stage),
    }));
    match result {
        Ok(Ok(())) => Outcome::default(),
        Ok(Err(Stop::Finding(message))) => Outcome {
            finding: Some(Finding {
                stage: stage.get(),
                message,
            }),
            known: None,
        },
        Err(payload) => Outcome {
            finding: Some(Finding {
                stage: stage.get(),
                message: format!(
                    "panic: {}",
                    payload
                        .downcast_ref::<String>()
                        .cloned()
                        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                        .unwrap_or_else(|| "(no message)".into())
                ),
            }),
            known: None,
        },
    }
}

fn graph_stages(case: &Case, stage: &Cell<&'static str>) -> Result<(), Stop> {
    let registry = Registry::builtin();
    let files: Arc<MemFiles> = Arc::new(MemFiles::new(case.files.clone()));
    let Ok(graph) = Graph::from_json_in(&case.text, registry, files.clone()) else {
        return Ok(());
    };
    stage.set("save");
    let saved = graph.to_json();
    match Graph::from_json_in(&saved, registry, files) {
        Ok(again) if again.to_json() == saved => {}
        Ok(_) => return Err("save → load → save is not byte-identical".to_owned().into()),
        Err(e) => return Err(format!("the saved graph does not load: {e:?}").into()),
    }
    compiled_stages(&graph, stage)
}

/// Plan, evaluate, WGSL and contract of a loaded graph.
fn compiled_stages(graph: &Graph, stage: &Cell<&'static str>) -> Result<(), Stop> {
    stage.set("plan");
    let Ok(plan) = Plan::compile(graph, &PlanOptions::default()) else {
        return Ok(());
    };
    stage.set("eval");
    let mut batch = SampleBatch::new(3);
    let _ = batch.set_values(
        Attribute::Normal,
        &[[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, -1.0, 0.0]],
    );
    let _ = plan.execute(&batch, &plan.default_parameters());
    stage.set("wgsl");
    for entry in [Entry::Compute, Entry::Fragment] {
        let options = WgslOptions {
            entry,
            ..Default::default()
        };
        match generate(graph, &options) {
            Err(e @ ShaderError::Naga { .. }) => {
                return Err(
                    format!("loads and plans, naga rejects its WGSL ({entry:?}): {e}").into(),
                );
            }
            Err(ShaderError::Plan(_)) | Ok(_) => {}
            Err(e) => return Err(format!("loads and plans, WGSL fails ({entry:?}): {e}").into()),
        }
    }
    stage.set("contract");
    match Material::new(graph, &MaterialOptions::default()) {
        Ok(material) => {
            let json = material.contract().to_json();
            if material.contract().to_json() != json {
                return Err("the contract is not the same bytes twice".to_owned().into());
            }
            if let Err(e) = serde_json::from_str::<serde_json::Value>(&json) {
                return Err(format!("the contract is not JSON: {e}").into());
            }
        }
        Err(MaterialError::Shader { source, .. })
            if matches!(*source, ShaderError::Naga { .. }) =>
        {
            return Err(
                format!("loads and plans, naga rejects its render module: {source}").into(),
            );
        }
        Err(_) => {}
    }
    Ok(())
}

/// The graph drawn in a scene case's tiny frame.
fn frame_graph() -> &'static Graph {
    static GRAPH: OnceLock<Graph> = OnceLock::new();
    GRAPH.get_or_init(|| {
        let text = include_str!("../../graphs/fresnel_glass.json");
        Graph::from_json(text, Registry::builtin()).expect("the bundled glass loads")
    })
}

fn scene_stages(text: &str, stage: &Cell<&'static str>) -> Result<(), Stop> {
    stage.set("scene");
    let Ok(scene) = Scene::from_json(text) else {
        return Ok(());
    };
    let saved = scene.to_json();
    match Scene::from_json(&saved) {
        Ok(again) if again.to_json() == saved => {}
        Ok(_) => {
            return Err("scene save → load → save is not byte-identical"
                .to_owned()
                .into());
        }
        Err(e) => return Err(format!("the saved scene does not load: {e}").into()),
    }
    stage.set("mesh");
    let budget = MemoryBudget::new(SCENE_BUDGET);
    if scene.reserve_meshes(&budget).is_err() {
        return Ok(());
    }
    let reserved = budget.used();
    let mesh = scene.material_mesh();
    if !mesh.is_consistent() {
        return Err("the material mesh is not consistent".to_owned().into());
    }
    let bytes = mesh.vertex_count() as u64 * matgraph::scene::MESH_VERTEX_BYTES
        + mesh.triangle_count() as u64 * matgraph::scene::MESH_TRIANGLE_BYTES;
    if bytes > reserved {
        return Err(format!(
            "the material mesh ({} vertices, {} triangles) needs more than its reservation ({reserved} bytes)",
            mesh.vertex_count(),
            mesh.triangle_count()
        )
        .into());
    }
    // A 4 × 4 frame now and then (the text's length picks it, so replays agree).
    if text.len().is_multiple_of(64) {
        stage.set("render");
        let options = matgraph::render::RenderOptions {
            width: 4,
            height: 4,
            memory_budget: SCENE_BUDGET,
            ..Default::default()
        };
        let _ = matgraph::render::render(frame_graph(), &scene, &options);
    }
    Ok(())
}

fn set_stages(case: &Case, stage: &Cell<&'static str>) -> Result<(), Stop> {
    stage.set("set");
    let registry = Registry::builtin();
    let Ok(given) = overrides::parse_all(&case.sets) else {
        return Ok(());
    };
    for o in &given {
        // Whatever parses holds only numbers an f32 holds.
        if let Some(x) = number_past_f32(&o.value) {
            return Err(format!("--set {}={} was accepted with {x}", o.name, o.text).into());
        }
    }
    let Ok(mut doc) = GraphDocument::parse(&case.text) else {
        return Ok(());
    };
    let Ok(rest) = overrides::apply_to_document(&mut doc, &given) else {
        return Ok(());
    };
    let files: Arc<MemFiles> = Arc::new(MemFiles::new(case.files.clone()));
    let Ok(graph) = Graph::with_variants_in(&doc, registry, &[], files) else {
        return Ok(());
    };
    stage.set("plan");
    let Ok(plan) = Plan::compile(&graph, &PlanOptions::default()) else {
        return Ok(());
    };
    let mut values = plan.default_parameters();
    if overrides::set_parameters(&plan, &mut values, &rest.parameters).is_err() {
        return Ok(());
    }
    stage.set("eval");
    let mut batch = SampleBatch::new(1);
    for (a, v) in rest.attributes {
        if batch.fill(a, v).is_err() {
            return Ok(());
        }
    }
    let _ = plan.execute(&batch, &values);
    Ok(())
}

/// A number of `v` that rounds to an f32 infinity, if any.
fn number_past_f32(v: &serde_json::Value) -> Option<f64> {
    match v {
        serde_json::Value::Number(n) => n.as_f64().filter(|x| !(*x as f32).is_finite()),
        serde_json::Value::Array(items) => items.iter().find_map(number_past_f32),
        serde_json::Value::Object(m) => m.values().find_map(number_past_f32),
        _ => None,
    }
}

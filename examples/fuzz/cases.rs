//! The corpus the cases start from (the bundled graphs, group library files and scenes,
//! read once before the run) and the case of each `(seed, case)`: its family and inputs.

use super::mutate_graph::{mutate, mutate_text};
use super::mutate_groups::mutate_groups;
use super::mutate_scene::mutate_scene;
use super::rng::Rng;
use super::set_values::overrides;
use matgraph::scene::{SCENE_PRESETS, Scene};
use serde_json::{Value as J, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a case exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Family {
    /// A version-1 (flat) graph: load, save, plan, evaluate, WGSL, contract.
    Graph,
    /// A version-2 graph with groups and group library files in memory.
    Grouped,
    /// A scene: parse, validate, save, reserve and build its meshes.
    Scene,
    /// `--set` overrides applied to a bundled graph, then planned and evaluated.
    Set,
}

impl Family {
    /// Every family.
    pub const ALL: [Family; 4] = [Family::Graph, Family::Grouped, Family::Scene, Family::Set];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Family::Graph => "graph-v1",
            Family::Grouped => "graph-v2",
            Family::Scene => "scene",
            Family::Set => "set",
        }
    }
}

/// The inputs of one case.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// Its family.
    pub family: Family,
    /// The graph text (families `Graph`, `Grouped`, `Set`) or the scene text (`Scene`).
    pub text: String,
    /// The other files of the graph's folder by path (`lib/fresnel.json`).
    pub files: BTreeMap<String, String>,
    /// The `--set` texts (family `Set`).
    pub sets: Vec<String>,
}

impl Case {
    /// The case as one JSON object, for `--show` and the findings' reproducers.
    pub fn to_json(&self, seed: u64, case: u64) -> String {
        serde_json::to_string_pretty(&json!({
            "fuzz_case": { "seed": seed, "case": case, "family": self.family.name() },
            "text": self.text,
            "files": self.files,
            "sets": self.sets,
        }))
        .unwrap_or_default()
    }
}

/// The inputs the cases mutate, parsed once.
pub struct Corpus {
    /// Flat graphs: the version-1 files, and the version-2 files inlined.
    pub flat: Vec<J>,
    /// The version-2 graphs as written (with groups and references to `lib/`).
    pub grouped: Vec<J>,
    /// The group library files by path (`lib/fresnel.json`).
    pub libs: Vec<(String, J)>,
    /// The preset scenes and the bundled graphs' inline scenes.
    pub scenes: Vec<J>,
}

/// The bundled graphs' folder.
fn graphs_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs")
}

/// The `.json` files of `dir`, sorted.
fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().is_some_and(|e| e == "json"));
    paths.sort();
    paths
}

impl Corpus {
    /// Reads the bundled graphs (`graphs/*.json`), their library (`graphs/lib/*.json`) and
    /// the scene presets.
    pub fn bundled() -> Corpus {
        let dir = graphs_dir();
        let registry = matgraph::Registry::builtin();
        let read = |p: &Path| -> Option<J> {
            serde_json::from_str(&std::fs::read_to_string(p).ok()?).ok()
        };
        let mut flat = Vec::new();
        let mut grouped = Vec::new();
        let mut scenes: Vec<J> = SCENE_PRESETS
            .iter()
            .filter_map(|n| serde_json::from_str(&Scene::preset(n)?.to_json()).ok())
            .collect();
        for p in json_files(&dir) {
            let Some(raw) = read(&p) else { continue };
            if raw["scene"].is_object() {
                scenes.push(raw["scene"].clone());
            }
            let g = matgraph::io::load_graph(&p, registry).ok();
            match g.filter(|g| g.has_groups()) {
                Some(g) => {
                    if let Ok(v) = serde_json::to_value(g.flat_document()) {
                        flat.push(v);
                    }
                    grouped.push(raw);
                }
                None => flat.push(raw),
            }
        }
        let libs = json_files(&dir.join("lib"))
            .iter()
            .filter_map(|p| {
                let name = p.file_name()?.to_str()?;
                Some((format!("lib/{name}"), read(p)?))
            })
            .collect();
        Corpus {
            flat,
            grouped,
            libs,
            scenes,
        }
    }

    /// The library files as texts by path.
    fn lib_texts(&self) -> BTreeMap<String, String> {
        self.libs
            .iter()
            .map(|(p, v)| (p.clone(), v.to_string()))
            .collect()
    }

    /// Case `case` of run `seed`.
    pub fn case(&self, seed: u64, case: u64) -> Case {
        let mut rng = Rng::new(seed, case);
        let family = match rng.below(20) {
            0..=7 => Family::Graph,
            8..=13 => Family::Grouped,
            14..=16 => Family::Scene,
            _ => Family::Set,
        };
        let mut files = BTreeMap::new();
        let mut sets = Vec::new();
        let text = match family {
            Family::Graph => {
                let mut doc = rng.pick(&self.flat).clone();
                for _ in 0..1 + rng.below(4) {
                    mutate(&mut rng, &mut doc);
                }
                finish(&mut rng, &doc)
            }
            Family::Grouped => {
                let mut doc = if self.grouped.is_empty() || rng.one_in(4) {
                    rng.pick(&self.flat).clone()
                } else {
                    rng.pick(&self.grouped).clone()
                };
                doc["version"] = json!(2);
                for _ in 0..1 + rng.below(4) {
                    mutate_groups(&mut rng, &mut doc, &self.libs, false);
                }
                files = self.lib_texts();
                if rng.one_in(4) && !self.libs.is_empty() {
                    // One library file mutated too (its references resolve from `lib/`).
                    let k = rng.below(self.libs.len());
                    let (path, lib) = &self.libs[k];
                    let mut lib = lib.clone();
                    mutate_groups(&mut rng, &mut lib, &self.libs, true);
                    files.insert(path.clone(), finish(&mut rng, &lib));
                }
                finish(&mut rng, &doc)
            }
            Family::Scene => {
                let mut doc = rng.pick(&self.scenes).clone();
                for _ in 0..1 + rng.below(3) {
                    mutate_scene(&mut rng, &mut doc, &self.scenes);
                }
                finish(&mut rng, &doc)
            }
            Family::Set => {
                let grouped = !self.grouped.is_empty() && rng.one_in(3);
                let doc = if grouped {
                    files = self.lib_texts();
                    rng.pick(&self.grouped).clone()
                } else {
                    rng.pick(&self.flat).clone()
                };
                sets = overrides(&mut rng, &doc);
                doc.to_string()
            }
        };
        Case {
            family,
            text,
            files,
            sets,
        }
    }
}

/// `doc` as text, pretty or compact, and now and then with raw byte edits.
fn finish(rng: &mut Rng, doc: &J) -> String {
    let text = if rng.one_in(2) {
        serde_json::to_string_pretty(doc).unwrap_or_default()
    } else {
        doc.to_string()
    };
    if rng.one_in(8) {
        let mut bytes = text.into_bytes();
        mutate_text(rng, &mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    } else {
        text
    }
}

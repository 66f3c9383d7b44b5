//! The exact rewrites: scene constants substituted, constants folded by the CPU plan, dead
//! nodes removed. Each works on the resolved document and re-validates it.

use super::{
    EnvironmentInfo, Rewrite, RewriteKind, SceneInfo, SpecialiseError, SpecialiseOptions,
    Specialised,
};
use crate::document::{GraphDocument, NodeDocument};
use crate::graph::{Graph, InputSource, OutputRef};
use crate::node::{Attribute, Evaluation};
use crate::plan::{Plan, PlanOptions};
use crate::registry::Registry;
use crate::types::SocketType;
use crate::value::Value;
use std::collections::{BTreeSet, HashMap, HashSet};

/// A value to put in place of a node output, with why.
#[derive(Clone, Debug)]
pub(super) struct Substitute {
    pub value: Value,
    pub kind: RewriteKind,
    pub reason: String,
}

/// The state of one specialisation.
pub(super) struct Specialiser<'a> {
    registry: &'a Registry,
    scene: &'a SceneInfo,
    options: &'a SpecialiseOptions,
    name: String,
    doc: GraphDocument,
    rewrites: Vec<Rewrite>,
    /// Nodes already replaced by their values (not listed again when removed).
    folded: HashSet<String>,
    /// The `constant` nodes the rewrites made.
    made: HashSet<String>,
}

impl<'a> Specialiser<'a> {
    /// Resolves the variants of `graph` and applies the parameter values to bake.
    pub(super) fn new(
        graph: &Graph,
        registry: &'a Registry,
        scene: &'a SceneInfo,
        options: &'a SpecialiseOptions,
    ) -> Result<Specialiser<'a>, SpecialiseError> {
        let choices: Vec<(String, String)> = graph.variant_choices().into_iter().collect();
        let invalid = |errors| SpecialiseError::Invalid {
            graph: graph.name.clone(),
            errors,
        };
        let mut doc = crate::variant::resolve(&graph.flat_document(), &choices).map_err(invalid)?;
        for (name, value) in options.bake_parameters.iter().flatten() {
            let param = graph.parameters().iter().find(|p| &p.name == name);
            let Some(p) = param else {
                return Err(SpecialiseError::Eval {
                    graph: graph.name.clone(),
                    error: Box::new(crate::plan::EvalError::UnknownParameter {
                        name: name.clone(),
                        suggestion: crate::registry::nearest(
                            name,
                            graph.parameters().iter().map(|p| p.name.as_str()),
                        )
                        .map(str::to_owned),
                    }),
                });
            };
            let id = &graph.nodes()[p.node].id;
            let v = value.convert(p.ty).unwrap_or(*value);
            if let Some(n) = doc.nodes.iter_mut().find(|n| &n.id == id) {
                n.inputs.insert("value".into(), v.to_json());
            }
        }
        Ok(Specialiser {
            registry,
            scene,
            options,
            name: graph.name.clone(),
            doc,
            rewrites: Vec::new(),
            folded: HashSet::new(),
            made: HashSet::new(),
        })
    }

    /// Runs every rewrite and validates the result.
    pub(super) fn run(mut self) -> Result<Specialised, SpecialiseError> {
        let g = self.build()?;
        let subst = self.scene_constants(&g);
        self.inline(&g, &subst);
        self.fold_and_prune()?;
        if self.options.approximate {
            let g = self.build()?;
            if super::thin_film::rewrite(
                &mut self.doc,
                &g,
                self.scene.coherence_length_nm,
                &mut self.rewrites,
            ) {
                self.fold_and_prune()?;
            }
        }
        let graph = self.build()?;
        Ok(Specialised {
            graph,
            document: self.doc,
            rewrites: self.rewrites,
        })
    }

    /// Constant folding through the CPU plan, then dead-node removal.
    fn fold_and_prune(&mut self) -> Result<(), SpecialiseError> {
        let g = self.build()?;
        let subst = self.plan_constants(&g)?;
        self.inline(&g, &subst);
        if self.options.bake_parameters.is_some() {
            self.doc.parameters.clear();
        }
        self.remove_dead();
        Ok(())
    }

    fn build(&self) -> Result<Graph, SpecialiseError> {
        Graph::from_document(&self.doc, self.registry).map_err(|errors| SpecialiseError::Invalid {
            graph: self.name.clone(),
            errors,
        })
    }

    /// The outputs the scene fixes: time, the one directional light, a constant environment.
    fn scene_constants(&self, g: &Graph) -> HashMap<OutputRef, Substitute> {
        let mut out = HashMap::new();
        let light = self.scene.single_directional();
        for (i, n) in g.nodes().iter().enumerate() {
            match n.node_type.evaluation() {
                Evaluation::Attributes(attrs) => {
                    for (k, a) in attrs.iter().enumerate() {
                        let s = match (a, self.scene.time, light) {
                            (Attribute::Time, Some(t), _) => Substitute {
                                value: Value::float(t),
                                kind: RewriteKind::Time,
                                reason: format!("time fixed at {t} s"),
                            },
                            (Attribute::Light, _, Some((d, _))) => Substitute {
                                value: Value::vec3(d),
                                kind: RewriteKind::LightDirection,
                                reason: format!(
                                    "one directional light: L = ({}, {}, {})",
                                    d[0], d[1], d[2]
                                ),
                            },
                            (Attribute::LightColor, _, Some((_, c)))
                                if !self.scene.shadow_casters =>
                            {
                                Substitute {
                                    value: Value::color(c),
                                    kind: RewriteKind::LightColor,
                                    reason: format!(
                                        "one directional light, no shadow casters: radiance ({}, {}, {})",
                                        c[0], c[1], c[2]
                                    ),
                                }
                            }
                            _ => continue,
                        };
                        out.insert(OutputRef { node: i, output: k }, s);
                    }
                }
                Evaluation::Texture => {
                    // Only the plain sampler reads the radiance itself: a texture node with a
                    // kernel of its own (env_ggx_monte_carlo integrates the environment
                    // against a BRDF) is not the environment's value.
                    let env = n.node_type.texture_kernel_fn().is_none()
                        && n.texture.as_ref().and_then(|t| t.scene_name()) == Some("environment");
                    if let (true, EnvironmentInfo::Constant(c)) = (env, self.scene.environment) {
                        let reason = format!(
                            "the environment is constant: ({}, {}, {})",
                            c[0], c[1], c[2]
                        );
                        for (k, o) in n.node_type.outputs().iter().enumerate() {
                            let value = match o.name {
                                "color" => Value::color(c),
                                "alpha" => Value::float(1.0),
                                _ => continue,
                            };
                            out.insert(
                                OutputRef { node: i, output: k },
                                Substitute {
                                    value,
                                    kind: RewriteKind::Environment,
                                    reason: reason.clone(),
                                },
                            );
                        }
                    }
                }
                _ => {}
            }
        }
        out
    }

    /// The outputs of live nodes the CPU plan folds into constants.
    fn plan_constants(&self, g: &Graph) -> Result<HashMap<OutputRef, Substitute>, SpecialiseError> {
        let plan = Plan::compile(
            g,
            &PlanOptions {
                outputs: Vec::new(),
                bake_parameters: self.options.bake_parameters.is_some(),
            },
        )
        .map_err(|error| SpecialiseError::Eval {
            graph: self.name.clone(),
            error: Box::new(error),
        })?;
        let mut out = HashMap::new();
        for (i, n) in g.nodes().iter().enumerate() {
            if !plan.is_live(i) {
                continue;
            }
            let parameter = n.node_type.evaluation() == Evaluation::Parameter;
            for (k, o) in n.node_type.outputs().iter().enumerate() {
                let r = OutputRef { node: i, output: k };
                let Some(value) = plan.folded(r) else {
                    continue;
                };
                let (kind, reason) = if parameter {
                    (
                        RewriteKind::Parameter,
                        format!("parameter baked at {value}"),
                    )
                } else {
                    (
                        RewriteKind::Fold,
                        format!("inputs all constant: {} = {value}", o.name),
                    )
                };
                out.insert(
                    r,
                    Substitute {
                        value,
                        kind,
                        reason,
                    },
                );
            }
        }
        Ok(out)
    }

    /// Puts the substitutes in place of the links that read them: a literal on the input
    /// where the port accepts it, else a `constant` node; graph outputs read a `constant`.
    fn inline(&mut self, g: &Graph, subst: &HashMap<OutputRef, Substitute>) {
        if subst.is_empty() {
            return;
        }
        let mut ids: HashSet<String> = self.doc.nodes.iter().map(|n| n.id.clone()).collect();
        let mut constants: HashMap<OutputRef, String> = HashMap::new();
        let mut new_nodes: Vec<NodeDocument> = Vec::new();
        let mut used: BTreeSet<(usize, RewriteKind)> = BTreeSet::new();
        let mut constant_for = |r: OutputRef, v: Value, new_nodes: &mut Vec<NodeDocument>| {
            if let Some(id) = constants.get(&r) {
                return Some(format!("{id}.value"));
            }
            let ty = g.output_type(r);
            if matches!(ty, SocketType::Int | SocketType::Bool) || !v.is_finite() {
                return None;
            }
            let src = &g.nodes()[r.node];
            let base = format!("{}__{}", src.id, src.node_type.outputs()[r.output].name);
            let mut id = base.clone();
            let mut k = 1;
            while !ids.insert(id.clone()) {
                k += 1;
                id = format!("{base}_{k}");
            }
            new_nodes.push(NodeDocument {
                id: id.clone(),
                node_type: "constant".into(),
                data_type: Some(ty.name().to_owned()),
                variant: None,
                group: None,
                muted: false,
                inputs: [(
                    "value".to_owned(),
                    Value::from_lanes(ty, v.lanes()).to_json(),
                )]
                .into_iter()
                .collect(),
                texture: None,
                color_space: None,
                position: src.position,
            });
            constants.insert(r, id.clone());
            Some(format!("{id}.value"))
        };
        let position: HashMap<String, usize> = self
            .doc
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.id.clone(), i))
            .collect();
        for n in g.nodes() {
            let Some(&p) = position.get(&n.id) else {
                continue;
            };
            let mut pin_generic = false;
            for (k, (decl, src)) in n.node_type.inputs().iter().zip(&n.inputs).enumerate() {
                let InputSource::Link(r, conv) = src else {
                    continue;
                };
                let Some(s) = subst.get(r) else {
                    continue;
                };
                let to = n.input_type(k);
                let seen = Value::from_lanes(to, &conv.apply(s.value.raw(), to));
                let in_range = decl.hard.is_none_or(|h| h.contains(&seen));
                let json = if seen.is_finite() && in_range {
                    literal_json(decl, &seen)
                } else {
                    match constant_for(*r, s.value, &mut new_nodes) {
                        Some(link) => serde_json::json!({ "link": link }),
                        None => continue,
                    }
                };
                self.doc.nodes[p].inputs.insert(decl.name.to_owned(), json);
                pin_generic = true;
                used.insert((r.node, s.kind));
            }
            if pin_generic && n.node_type.is_generic() && self.doc.nodes[p].data_type.is_none() {
                self.doc.nodes[p].data_type = Some(n.generic.name().to_owned());
            }
        }
        for (k, o) in g.outputs().iter().enumerate() {
            let Some(s) = subst.get(&o.source) else {
                continue;
            };
            if g.nodes()[o.source.node].node_type.name() == "constant" {
                continue;
            }
            if let Some(link) = constant_for(o.source, s.value, &mut new_nodes) {
                self.doc.outputs[k].from = link;
                used.insert((o.source.node, s.kind));
            }
        }
        self.made.extend(new_nodes.iter().map(|n| n.id.clone()));
        self.doc.nodes.extend(new_nodes);
        for (node, kind) in used {
            let n = &g.nodes()[node];
            let reason = n
                .node_type
                .outputs()
                .iter()
                .enumerate()
                .filter_map(|(k, _)| subst.get(&OutputRef { node, output: k }))
                .filter(|s| s.kind == kind)
                .map(|s| s.reason.clone())
                .collect::<Vec<_>>();
            let reason = dedup_join(reason);
            if matches!(kind, RewriteKind::Fold | RewriteKind::Parameter) {
                self.folded.insert(n.id.clone());
            }
            self.rewrites.push(Rewrite {
                node: n.id.clone(),
                kind,
                reason,
            });
        }
    }

    /// Removes the nodes that reach no graph output (exposed parameters are kept).
    fn remove_dead(&mut self) {
        let index: HashMap<&str, usize> = self
            .doc
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| (n.id.as_str(), i))
            .collect();
        let mut live: HashSet<&str> = HashSet::new();
        let mut stack: Vec<&str> = self
            .doc
            .outputs
            .iter()
            .filter_map(|o| o.from.split_once('.').map(|p| p.0))
            .chain(self.doc.parameters.iter().map(|p| p.node.as_str()))
            .collect();
        while let Some(id) = stack.pop() {
            if let Some(&i) = index.get(id)
                && live.insert(id)
            {
                stack.extend(self.doc.nodes[i].inputs.values().filter_map(link_id));
            }
        }
        let live: HashSet<String> = live.into_iter().map(str::to_owned).collect();
        let mut dead = Vec::new();
        self.doc.nodes.retain(|n| {
            let keep = live.contains(&n.id);
            if !keep {
                dead.push(n.id.clone());
            }
            keep
        });
        for id in dead {
            if self.folded.contains(&id) || self.made.contains(&id) {
                continue;
            }
            self.rewrites.push(Rewrite {
                node: id,
                kind: RewriteKind::Dead,
                reason: "reaches no output once the scene's constants are folded".into(),
            });
        }
    }
}

/// Joins reasons, each once.
fn dedup_join(reasons: Vec<String>) -> String {
    let mut seen = Vec::new();
    for r in reasons {
        if !seen.contains(&r) {
            seen.push(r);
        }
    }
    seen.join("; ")
}

/// The JSON literal of `v` on input `decl`: an enum input's choice name, else the value.
fn literal_json(decl: &crate::node::InputDecl, v: &Value) -> serde_json::Value {
    if !decl.choices.is_empty()
        && let Some(name) = usize::try_from(v.as_i32())
            .ok()
            .and_then(|i| decl.choices.get(i))
    {
        return serde_json::Value::String((*name).to_owned());
    }
    v.to_json()
}

/// The node id of a link entry `{"link": "node.output"}`.
pub(super) fn link_id(json: &serde_json::Value) -> Option<&str> {
    json.as_object()
        .filter(|o| o.len() == 1)?
        .get("link")?
        .as_str()?
        .split_once('.')
        .map(|p| p.0)
}

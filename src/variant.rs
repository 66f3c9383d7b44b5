//! Variants: named choices between alternative implementations of a model (Unreal's
//! quality switch, MaterialX's variants), resolved at compile time.
//!
//! A graph declares `"variants": {"fresnel": {"choices": ["schlick", "exact"], "default":
//! "exact"}}`, and a `switch` node names one (`"variant": "fresnel"`) with one linked input per
//! choice. Its output `result` is the chosen input's link: resolving rewires every consumer of
//! the switch to the chosen source, so the unchosen branches have no consumer and the plan
//! (which keeps only nodes that reach an output) drops them before codegen. [`resolve`]
//! goes further and removes the dead nodes from the document itself.

use crate::document::{GraphDocument, NodeDocument, VariantDocument};
use crate::error::GraphError;
use crate::registry::nearest;
use std::collections::{BTreeMap, HashMap, HashSet};

/// The node type name of a switch.
pub const SWITCH: &str = "switch";
/// The name of a switch's one output.
pub const SWITCH_OUTPUT: &str = "result";

/// A selection of choices: `(variant, choice)` pairs; variants not named take their default.
pub type Selection = [(String, String)];

/// What rewiring replaced, so that a graph saves as written.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Written {
    /// The declared variants.
    pub variants: BTreeMap<String, VariantDocument>,
    /// The choice made for each variant.
    pub chosen: BTreeMap<String, String>,
    /// The switch nodes with their index in the file's node list.
    pub switches: Vec<(usize, NodeDocument)>,
    /// `(node id, input) → link as written` for every rewired input.
    pub links: HashMap<(String, String), String>,
    /// `output index → from as written` for every rewired graph output.
    pub outputs: HashMap<usize, String>,
}

/// Checks the variants and switches of `doc`, picks each variant's choice (`selection`, else
/// its default), and returns the document without its switches, every link through one
/// rewired to the chosen source, and a record of what was replaced. Nodes are not removed.
pub(crate) fn rewire(
    doc: &GraphDocument,
    selection: &Selection,
) -> Result<(GraphDocument, Written), Vec<GraphError>> {
    let mut errors = Vec::new();
    let chosen = choices(doc, selection, &mut errors);
    let ids: HashSet<&str> = doc
        .nodes
        .iter()
        .filter(|n| n.node_type != SWITCH)
        .map(|n| n.id.as_str())
        .collect();
    // Switch id → the link its chosen input holds.
    let mut picks: HashMap<&str, &str> = HashMap::new();
    let mut switches = Vec::new();
    for (i, n) in doc.nodes.iter().enumerate() {
        if n.node_type != SWITCH {
            if n.variant.is_some() {
                errors.push(GraphError::BadSwitch {
                    node: n.id.clone(),
                    message: format!("only '{SWITCH}' nodes name a variant"),
                    suggestion: None,
                });
            }
            continue;
        }
        switches.push((i, n.clone()));
        if ids.contains(n.id.as_str()) || picks.contains_key(n.id.as_str()) {
            errors.push(GraphError::DuplicateId { node: n.id.clone() });
        }
        if let Some(pick) = check_switch(doc, n, &chosen, &mut errors) {
            picks.insert(&n.id, pick);
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let follow = |node: &str, input: &str, link: &str, errors: &mut Vec<GraphError>| {
        let (mut link, mut hopped) = (link, false);
        for _ in 0..=picks.len() {
            let (id, output) = link.split_once('.')?;
            let Some(next) = picks.get(id) else {
                return hopped.then(|| link.to_owned());
            };
            if output != SWITCH_OUTPUT {
                errors.push(GraphError::MissingOutput {
                    node: node.to_owned(),
                    input: input.to_owned(),
                    target: id.to_owned(),
                    output: output.to_owned(),
                    suggestion: Some(SWITCH_OUTPUT.to_owned()),
                });
                return None;
            }
            (link, hopped) = (next, true);
        }
        errors.push(GraphError::BadSwitch {
            node: node.to_owned(),
            message: "switches link to each other in a cycle".into(),
            suggestion: None,
        });
        None
    };
    let mut out = doc.clone();
    out.variants = BTreeMap::new();
    out.nodes.retain(|n| n.node_type != SWITCH);
    let mut written = Written {
        variants: doc.variants.clone(),
        chosen,
        switches,
        ..Written::default()
    };
    // Switches linking switches: follow the chain (checked for cycles) from each switch too.
    for (_, s) in &written.switches {
        for (input, json) in &s.inputs {
            if let Some(l) = link_of(json) {
                follow(&s.id, input, l, &mut errors);
            }
        }
    }
    for n in &mut out.nodes {
        for (input, json) in n.inputs.iter_mut() {
            let Some(l) = link_of(json).map(str::to_owned) else {
                continue;
            };
            if let Some(to) = follow(&n.id, input, &l, &mut errors) {
                *json = serde_json::json!({ "link": to });
                written.links.insert((n.id.clone(), input.clone()), l);
            }
        }
    }
    for (k, o) in out.outputs.iter_mut().enumerate() {
        if let Some(to) = follow("", "", &o.from.clone(), &mut Vec::new()) {
            written
                .outputs
                .insert(k, std::mem::replace(&mut o.from, to));
        }
    }
    if errors.is_empty() {
        Ok((out, written))
    } else {
        Err(errors)
    }
}

/// Resolves the variants of `doc` at `selection` (defaults for variants not named): the
/// result has no variants and no switches, every link through a switch goes to the chosen
/// source, and the nodes only the unchosen branches used are removed. Nodes that reach a
/// graph output, exposed parameters, and nodes nothing consumes in the file are kept.
pub fn resolve(
    doc: &GraphDocument,
    selection: &Selection,
) -> Result<GraphDocument, Vec<GraphError>> {
    let (mut out, written) = rewire(doc, selection)?;
    // Candidates: everything upstream of an unchosen switch input.
    let index: HashMap<&str, usize> = doc
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.id.as_str(), i))
        .collect();
    let mut candidates = HashSet::new();
    let mut stack: Vec<&str> = Vec::new();
    for (_, s) in &written.switches {
        let choice = s.variant.as_ref().and_then(|v| written.chosen.get(v));
        for (input, json) in &s.inputs {
            if Some(input) != choice
                && let Some(l) = link_of(json)
            {
                stack.extend(l.split_once('.').map(|(id, _)| id));
            }
        }
    }
    while let Some(id) = stack.pop() {
        if let Some(&i) = index.get(id)
            && candidates.insert(id)
        {
            stack.extend(doc.nodes[i].inputs.values().filter_map(|j| link_id(j)));
        }
    }
    // Live: upstream of the outputs, the parameters and the file's own sinks.
    let consumed: HashSet<&str> = doc
        .nodes
        .iter()
        .flat_map(|n| n.inputs.values().filter_map(|j| link_id(j)))
        .chain(
            doc.outputs
                .iter()
                .filter_map(|o| o.from.split_once('.').map(|p| p.0)),
        )
        .collect();
    let out_index: HashMap<String, usize> = out
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.id.clone(), i))
        .collect();
    let mut live: HashSet<String> = HashSet::new();
    let mut stack: Vec<String> = out
        .outputs
        .iter()
        .filter_map(|o| o.from.split_once('.').map(|p| p.0.to_owned()))
        .chain(out.parameters.iter().map(|p| p.node.clone()))
        .chain(
            out.nodes
                .iter()
                .filter(|n| !consumed.contains(n.id.as_str()))
                .map(|n| n.id.clone()),
        )
        .collect();
    while let Some(id) = stack.pop() {
        if let Some(&i) = out_index.get(&id)
            && live.insert(id)
        {
            stack.extend(
                out.nodes[i]
                    .inputs
                    .values()
                    .filter_map(|j| link_id(j).map(str::to_owned)),
            );
        }
    }
    out.nodes
        .retain(|n| live.contains(&n.id) || !candidates.contains(n.id.as_str()));
    Ok(out)
}

/// The choice of every declared variant; bad declarations and selections are errors.
fn choices(
    doc: &GraphDocument,
    selection: &Selection,
    errors: &mut Vec<GraphError>,
) -> BTreeMap<String, String> {
    let bad = |variant: &str, field: &str, message: String, suggestion: Option<&str>| {
        GraphError::BadVariant {
            variant: variant.to_owned(),
            field: field.to_owned(),
            message,
            suggestion: suggestion.map(str::to_owned),
        }
    };
    let mut chosen = BTreeMap::new();
    for (name, v) in &doc.variants {
        if !crate::graph::valid_id(name) {
            errors.push(bad(
                name,
                "name",
                "use letters, digits, '_' and '-'".into(),
                None,
            ));
        }
        if v.choices.is_empty() {
            errors.push(bad(
                name,
                "choices",
                "needs at least one choice".into(),
                None,
            ));
        }
        let mut seen = HashSet::new();
        for c in &v.choices {
            if !seen.insert(c) {
                errors.push(bad(
                    name,
                    "choices",
                    format!("choice '{c}' is repeated"),
                    None,
                ));
            } else if !crate::graph::valid_id(c) {
                errors.push(bad(
                    name,
                    "choices",
                    format!("choice '{c}': use letters, digits, '_' and '-'"),
                    None,
                ));
            }
        }
        if !v.choices.contains(&v.default) {
            let near = nearest(&v.default, v.choices.iter().map(String::as_str));
            errors.push(bad(
                name,
                "default",
                format!("'{}' is not one of its choices", v.default),
                near,
            ));
        }
        chosen.insert(name.clone(), v.default.clone());
    }
    for (variant, choice) in selection {
        let selection_error =
            |message: String, suggestion: Option<&str>| GraphError::BadSelection {
                variant: variant.clone(),
                choice: choice.clone(),
                message,
                suggestion: suggestion.map(str::to_owned),
            };
        match doc.variants.get(variant) {
            None => errors.push(selection_error(
                if doc.variants.is_empty() {
                    "the graph declares no variants".into()
                } else {
                    format!("unknown variant '{variant}'")
                },
                nearest(variant, doc.variants.keys().map(String::as_str)),
            )),
            Some(v) if !v.choices.contains(choice) => errors.push(selection_error(
                format!(
                    "unknown choice '{choice}' (choices: {})",
                    v.choices.join(", ")
                ),
                nearest(choice, v.choices.iter().map(String::as_str)),
            )),
            Some(_) => {
                chosen.insert(variant.clone(), choice.clone());
            }
        }
    }
    chosen
}

/// Checks one switch node; returns the link of its chosen input.
fn check_switch<'d>(
    doc: &'d GraphDocument,
    n: &'d NodeDocument,
    chosen: &BTreeMap<String, String>,
    errors: &mut Vec<GraphError>,
) -> Option<&'d str> {
    let Some(name) = &n.variant else {
        errors.push(GraphError::BadSwitch {
            node: n.id.clone(),
            message: format!("a '{SWITCH}' node names the variant it follows"),
            suggestion: None,
        });
        return None;
    };
    let Some(v) = doc.variants.get(name) else {
        errors.push(GraphError::BadSwitch {
            node: n.id.clone(),
            message: format!("variant '{name}' is not declared in \"variants\""),
            suggestion: nearest(name, doc.variants.keys().map(String::as_str)).map(str::to_owned),
        });
        return None;
    };
    let input_error =
        |input: &str, message: String, suggestion: Option<&str>| GraphError::BadSwitchInput {
            node: n.id.clone(),
            input: input.to_owned(),
            message,
            suggestion: suggestion.map(str::to_owned),
        };
    if n.data_type.is_some() || n.texture.is_some() {
        errors.push(GraphError::BadSwitch {
            node: n.id.clone(),
            message: "a switch takes its type from its inputs: drop data_type and texture".into(),
            suggestion: None,
        });
    }
    for (input, json) in &n.inputs {
        if !v.choices.contains(input) {
            errors.push(input_error(
                input,
                format!("not a choice of variant '{name}'"),
                nearest(input, v.choices.iter().map(String::as_str)),
            ));
        } else if link_of(json).is_none() {
            errors.push(input_error(
                input,
                "a switch input must be a link {\"link\": \"node_id.output\"}".into(),
                None,
            ));
        }
    }
    for c in &v.choices {
        if !n.inputs.contains_key(c) {
            errors.push(input_error(
                c,
                format!("missing: variant '{name}' needs a link for each of its choices"),
                None,
            ));
        }
    }
    let choice = chosen.get(name)?;
    n.inputs.get(choice).and_then(link_of)
}

/// The text of a link entry `{"link": "node.output"}` with a `.` in it.
fn link_of(json: &serde_json::Value) -> Option<&str> {
    let obj = json.as_object()?;
    (obj.len() == 1)
        .then(|| obj.get("link")?.as_str())
        .flatten()
        .filter(|l| l.contains('.'))
}

/// The node id a link entry names.
fn link_id(json: &serde_json::Value) -> Option<&str> {
    link_of(json).and_then(|l| l.split_once('.')).map(|p| p.0)
}

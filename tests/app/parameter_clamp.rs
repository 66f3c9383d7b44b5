//! Parameters in the contract (issue 38 item 2): each `parameter` member carries its kind,
//! unit, soft and hard range, doc and group, and the modules clamp a raw value outside the
//! hard range to it (`ParameterClamp::HardRange`, the default), or read it as written
//! (`ParameterClamp::None`, `matgraph wgsl --no-clamp`).

use crate::app_contract::{device, run_library};
use crate::common::bundled_graphs;
use matgraph::Registry;
use matgraph::material::{BlockMember, Material, MaterialOptions};
use matgraph::wgsl::ParameterClamp;

fn load(name: &str) -> matgraph::Graph {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("graphs/{name}.json"));
    matgraph::io::load_graph(&path, Registry::builtin()).unwrap()
}

/// The contract's member for parameter `name`.
fn member<'a>(members: &'a [BlockMember], name: &str) -> &'a BlockMember {
    members
        .iter()
        .find(|m| m.parameter.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no parameter member '{name}'"))
}

#[test]
fn contract_parameters_carry_kind_unit_ranges_and_doc() {
    let glass = Material::new(&load("pbr_glass"), &MaterialOptions::default()).unwrap();
    let c = glass.contract();
    assert_eq!(c.parameters.clamp.as_deref(), Some("hard-range"));
    let m = &c.parameters.members;
    // pbr_glass.json: `ior` range [1, 3] in the file (the fresnel input's own hard range,
    // [0.001, 100], is wider), no unit.
    let ior = member(m, "ior");
    assert_eq!(ior.kind.as_deref(), Some("scalar"));
    assert_eq!(ior.hard_range, Some([1.0, 3.0]));
    assert_eq!(ior.unit, None);
    assert!(ior.doc.as_deref().is_some_and(|d| !d.is_empty()));
    // An RGB absorption coefficient in 1/m is a vector, not a colour to pick.
    let absorption = member(m, "absorption");
    assert_eq!(absorption.kind.as_deref(), Some("vector"));
    assert_eq!(absorption.unit.as_deref(), Some("1/m"));
    assert_eq!(absorption.hard_range, Some([0.0, 100.0]));
    let center = member(m, "center");
    assert_eq!(center.kind.as_deref(), Some("point"));
    assert_eq!(center.unit.as_deref(), Some("m"));

    let skin = Material::new(&load("skin"), &MaterialOptions::default()).unwrap();
    let c = skin.contract();
    let m = &c.parameters.members;
    let sheen = member(m, "sheen_color");
    assert_eq!(sheen.kind.as_deref(), Some("color"));
    assert_eq!(sheen.group.as_deref(), Some("sebum"));
    // skin.json: power range [1, 1000]; the Phong exponent's slider stops at 200.
    let power = member(m, "power");
    assert_eq!(power.hard_range, Some([1.0, 1000.0]));
    assert_eq!(power.range, Some([1.0, 200.0]));
    let off = Material::new(
        &load("skin"),
        &MaterialOptions {
            clamp: ParameterClamp::None,
            ..MaterialOptions::default()
        },
    )
    .unwrap();
    assert_eq!(off.contract().parameters.clamp.as_deref(), Some("none"));
}

#[test]
fn every_bundled_parameter_has_a_kind_and_a_hard_range_holding_its_slider_and_default() {
    for path in bundled_graphs() {
        let graph = matgraph::io::load_graph(&path, Registry::builtin()).unwrap();
        let c = Material::new(&graph, &MaterialOptions::default())
            .unwrap()
            .contract();
        for m in c
            .parameters
            .members
            .iter()
            .filter(|m| m.source == "parameter")
        {
            let at = format!("{}: {}", path.display(), m.name);
            assert!(m.kind.is_some(), "{at}: no kind");
            let [lo, hi] = m
                .hard_range
                .unwrap_or_else(|| panic!("{at}: no hard range"));
            let [slo, shi] = m.range.unwrap_or_else(|| panic!("{at}: no range"));
            assert!(lo <= slo && slo <= shi && shi <= hi, "{at}: {m:?}");
            let default: Vec<f64> = match m.default.as_ref().unwrap() {
                serde_json::Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap()).collect(),
                x => vec![x.as_f64().unwrap()],
            };
            for d in default {
                assert!(
                    f64::from(lo) <= d && d <= f64::from(hi),
                    "{at}: default {d}"
                );
            }
        }
    }
}

/// A graph whose outputs are its two parameters: `k` (float, range [0.25, 2]) as alpha and
/// `tint` (colour, range [0, 1]) as colour.
const PASS_THROUGH: &str = r#"{
  "version": 1, "name": "clamp_probe",
  "nodes": [
    { "id": "k", "type": "parameter", "inputs": { "value": 1.0 } },
    { "id": "tint", "type": "parameter", "inputs": { "value": [0.5, 0.5, 0.5] } }
  ],
  "outputs": [{ "name": "color", "from": "tint.value" }, { "name": "alpha", "from": "k.value" }],
  "parameters": [
    { "name": "k", "node": "k", "range": [0.25, 2.0] },
    { "name": "tint", "node": "tint", "range": [0.0, 1.0] }
  ]
}"#;

/// Seeded f32 values in [−10, 10] (exactly representable), then hard cases.
fn raw_values() -> Vec<f32> {
    let mut state = 0x9e37_79b9u32;
    let mut v: Vec<f32> = (0..24)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state >> 8) as f32 / 16_777_216.0 * 20.0 - 10.0
        })
        .collect();
    v.extend([
        -5.0,
        0.0,
        0.25,
        2.0,
        7.0,
        1e30,
        -1e30,
        f32::MIN_POSITIVE,
        1e-45,
    ]);
    v
}

/// The library module, run with raw parameter bytes: clamped (default) it returns each value
/// clamped to the file's range in f64; unclamped, the value written.
#[test]
fn raw_parameter_values_outside_the_hard_range_render_clamped() {
    const TEST: &str = "raw_parameter_values_outside_the_hard_range_render_clamped";
    let Some((device, queue)) = device(TEST) else {
        return;
    };
    let graph = matgraph::Graph::from_json(PASS_THROUGH, Registry::builtin()).unwrap();
    let set = matgraph::texture::TextureSet::default();
    for clamp in [ParameterClamp::HardRange, ParameterClamp::None] {
        let material = Material::new(
            &graph,
            &MaterialOptions {
                clamp,
                ..MaterialOptions::default()
            },
        )
        .unwrap();
        let block = material.library_params();
        let (k_at, tint_at) = (
            block.offset_of("k").unwrap() as usize,
            block.offset_of("tint").unwrap() as usize,
        );
        // The CPU refuses what the GPU clamps.
        assert!(material.params().set("k", -5.0f32).is_err());
        for x in raw_values() {
            let mut bytes = block.bytes();
            let tint = [x, -x, x * 0.1];
            bytes[k_at..k_at + 4].copy_from_slice(&x.to_le_bytes());
            for (c, t) in tint.iter().enumerate() {
                let at = tint_at + 4 * c;
                bytes[at..at + 4].copy_from_slice(&t.to_le_bytes());
            }
            let out = run_library(
                &device,
                &queue,
                &material,
                &set,
                &bytes,
                &[[0.5, 0.5, 0.0, 0.0]],
                "vec4<f32>(o.color, o.alpha)",
            )[0];
            let expect = |v: f32, lo: f64, hi: f64| match clamp {
                ParameterClamp::HardRange => f64::from(v).clamp(lo, hi) as f32,
                ParameterClamp::None => v,
            };
            let want = [
                expect(tint[0], 0.0, 1.0),
                expect(tint[1], 0.0, 1.0),
                expect(tint[2], 0.0, 1.0),
                expect(x, 0.25, 2.0),
            ];
            // Subnormal inputs may be flushed to zero by a GPU (WGSL §15.7).
            let same = |a: f32, b: f32| {
                a == b || (a.abs() < f32::MIN_POSITIVE && b.abs() < f32::MIN_POSITIVE)
            };
            assert!(
                out.iter().zip(want).all(|(&a, b)| same(a, b)),
                "{clamp:?}, k = {x:e}: got {out:?}, want {want:?}"
            );
        }
    }
}

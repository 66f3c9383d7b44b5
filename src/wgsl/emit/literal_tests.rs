//! Float literals read back by naga (an independent WGSL parser) to the same f32 bits.

use super::{float_literal, literal};
use crate::value::Value;

/// SplitMix64: a seeded source of bit patterns.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// Finite f32 values that sit on an edge of the format, both signs.
fn edge_values() -> Vec<f32> {
    let mut v = vec![
        0.0,
        1.0,
        0.1,
        1.0 / 3.0,
        f32::MAX,
        f32::from_bits(f32::MAX.to_bits() - 1),
        f32::from_bits(f32::MAX.to_bits() - 2),
        f32::MIN_POSITIVE,
        f32::from_bits(f32::MIN_POSITIVE.to_bits() - 1),
        f32::from_bits(f32::MIN_POSITIVE.to_bits() + 1),
        f32::from_bits(1),
        f32::from_bits(2),
        f32::from_bits(3),
        f32::EPSILON,
        1.0 + f32::EPSILON,
        1.0 - f32::EPSILON / 2.0,
        16_777_216.0,
        16_777_217.0,
        3.402_823_5e38,
        1e38,
        1e-38,
        std::f32::consts::PI,
    ];
    // Every binade's first and last value.
    for e in 0..255u32 {
        v.push(f32::from_bits(e << 23));
        v.push(f32::from_bits((e << 23) | 0x7f_ffff));
    }
    let neg: Vec<f32> = v.iter().map(|x| -x).collect();
    v.extend(neg);
    v
}

/// Edge values and 5 000 seeded random finite bit patterns.
fn test_values() -> Vec<f32> {
    let mut v = edge_values();
    let mut rng = SplitMix(0x6d61_7467_7261_7068);
    while v.len() < 5_000 + edge_values().len() {
        let x = f32::from_bits(rng.next() as u32);
        if x.is_finite() {
            v.push(x);
        }
    }
    v
}

/// The f32 bits of each `const` of a naga-parsed module, in declaration order.
fn naga_constants(source: &str) -> Vec<u32> {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("naga rejects:\n{}", e.emit_to_string(source)));
    module
        .constants
        .iter()
        .map(|(_, c)| match module.global_expressions[c.init] {
            naga::Expression::Literal(naga::Literal::F32(x)) => x.to_bits(),
            ref e => panic!("constant {:?} is not an f32 literal: {e:?}", c.name),
        })
        .collect()
}

#[test]
fn float_literals_read_back_by_naga_to_the_same_bits() {
    let values = test_values();
    let mut source = String::new();
    for (i, x) in values.iter().enumerate() {
        source.push_str(&format!("const c{i}: f32 = {};\n", float_literal(*x)));
    }
    let got = naga_constants(&source);
    assert_eq!(got.len(), values.len());
    for (x, bits) in values.iter().zip(got) {
        assert_eq!(
            bits,
            x.to_bits(),
            "{x:e} printed as {} reads back as {:e}",
            float_literal(*x),
            f32::from_bits(bits)
        );
    }
}

#[test]
fn float_literals_stay_in_f32_range_as_abstract_floats() {
    // WGSL reads the literal as an f64 first; Tint rejects one beyond f32::MAX.
    for x in test_values() {
        let s = float_literal(x);
        let d: f64 = s.parse().unwrap();
        assert!(
            d.abs() <= 340_282_346_638_528_859_811_704_183_484_516_925_440.0,
            "{s}"
        );
        assert!(
            s.contains('.') || s.contains('e'),
            "{s} is not a float literal"
        );
    }
}

#[test]
fn float_literal_spellings() {
    // Shortest decimals where they read back; f32::MAX's exact value where its shortest
    // decimal (3.4028235e38) exceeds it.
    assert_eq!(float_literal(1.0), "1.0");
    assert_eq!(float_literal(0.1), "0.1");
    assert_eq!(float_literal(-0.0), "-0.0");
    assert_eq!(float_literal(f32::from_bits(1)), "1e-45");
    assert_eq!(float_literal(f32::MAX), "3.4028234663852886e38");
    assert_eq!(float_literal(-f32::MAX), "-3.4028234663852886e38");
    assert_eq!(
        float_literal(f32::from_bits(f32::MAX.to_bits() - 1)),
        "3.4028233e38"
    );
}

#[test]
fn vector_literals_read_back_by_naga() {
    let v = Value::vec3([f32::MAX, f32::from_bits(1), -0.1]);
    let source = format!("const v: vec3<f32> = {};\n", literal(&v));
    let module = naga::front::wgsl::parse_str(&source).unwrap();
    let (_, c) = module.constants.iter().next().unwrap();
    let naga::Expression::Compose { ref components, .. } = module.global_expressions[c.init] else {
        panic!("not a composite: {:?}", module.global_expressions[c.init]);
    };
    let bits: Vec<u32> = components
        .iter()
        .map(|&h| match module.global_expressions[h] {
            naga::Expression::Literal(naga::Literal::F32(x)) => x.to_bits(),
            ref e => panic!("{e:?}"),
        })
        .collect();
    assert_eq!(
        bits,
        [f32::MAX.to_bits(), 1, (-0.1f32).to_bits()],
        "{source}"
    );
}

#[test]
fn non_finite_constants_are_runtime_bitcasts_naga_reads_back() {
    let values = [
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        f32::from_bits(0xffc0_0001),
    ];
    let mut source = String::from(super::NON_FINITE_WGSL);
    for (i, x) in values.iter().enumerate() {
        source.push_str(&format!(
            "fn f{i}() -> f32 {{ return {}; }}\n",
            float_literal(*x)
        ));
    }
    let module = naga::front::wgsl::parse_str(&source).unwrap();
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{e:?}\n{source}"));
    // Each f{i} calls the helper with the value's bits as a u32 literal.
    for (_, f) in module.functions.iter().skip(1) {
        let call_args = f.body.iter().find_map(|s| match s {
            naga::Statement::Call { arguments, .. } => Some(arguments.clone()),
            _ => None,
        });
        let arg = call_args.expect("a call of the helper")[0];
        let naga::Expression::Literal(naga::Literal::U32(bits)) = f.expressions[arg] else {
            panic!("{:?}", f.expressions[arg]);
        };
        let k: usize = f.name.as_deref().unwrap()[1..].parse().unwrap();
        assert_eq!(bits, values[k].to_bits(), "{}", float_literal(values[k]));
    }
}

/// `node tests/tint/check.mjs FILES` (Tint through Dawn's node bindings), or `None` after a
/// visible `SKIPPED` line; fails instead when `MATGRAPH_REQUIRE_TOOLS` is set (CI).
fn run_tint(test: &str, files: &[std::path::PathBuf]) -> Option<(i32, String)> {
    use std::io::Write as _;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tint");
    let run = if dir.join("node_modules/webgpu/package.json").is_file() {
        std::process::Command::new("node")
            .arg(dir.join("check.mjs"))
            .args(files)
            .output()
            .map_err(|e| format!("node: {e}"))
    } else {
        Err("tests/tint/node_modules is missing (npm ci --prefix tests/tint)".into())
    };
    match run {
        Ok(o) => Some((
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )),
        Err(why) => {
            assert!(
                std::env::var_os("MATGRAPH_REQUIRE_TOOLS").is_none(),
                "{test}: MATGRAPH_REQUIRE_TOOLS is set and Tint is missing: {why}"
            );
            // Written to the stream itself so that it shows without `--nocapture`.
            let _ = writeln!(std::io::stderr(), "SKIPPED {test}: Tint: {why}");
            None
        }
    }
}

#[test]
fn float_literals_read_back_by_tint_to_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let mut source = String::new();
    for x in test_values() {
        let bits = if x == 0.0 {
            // WGSL lets an implementation ignore the sign of a zero, and Tint's constant
            // evaluation makes -0.0 (however written: -0.0, -0.0f, -f32(0.0)) into +0.0.
            0
        } else {
            x.to_bits()
        };
        source.push_str(&format!(
            "const_assert bitcast<u32>(f32({})) == 0x{bits:08x}u;\n",
            float_literal(x),
        ));
    }
    let all = dir.path().join("literals.wgsl");
    std::fs::write(&all, &source).unwrap();
    // A control that must fail, so that a checker ignoring const_assert cannot pass.
    let control = dir.path().join("control.wgsl");
    std::fs::write(
        &control,
        "const_assert bitcast<u32>(f32(0.1)) == 0x3dcccccbu;\n",
    )
    .unwrap();
    let test = "float_literals_read_back_by_tint_to_the_same_bits";
    let Some((status, out)) = run_tint(test, &[all.clone(), control.clone()]) else {
        return;
    };
    let diagnostics: Vec<&str> = out.lines().filter(|l| l.contains(": error: ")).collect();
    assert_eq!(status, 1, "{out}");
    assert_eq!(diagnostics.len(), 1, "{}", diagnostics.join("\n"));
    assert!(
        diagnostics[0].starts_with(&format!("{}:1:", control.display())),
        "{}",
        diagnostics[0]
    );
}

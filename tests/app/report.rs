//! `matgraph report` in its quick mode (the shape of every family's table, the reference's
//! zero error, same bytes without timing) and `--max-error` on a closed-form case.

use matgraph::report::family::FAMILIES;
use std::path::Path;
use std::process::{Command, Output};

fn matgraph(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("XDG_RUNTIME_DIR", "/tmp")
        .output()
        .expect("the binary runs")
}

fn ok(out: &Output) -> String {
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");
    format!("{stdout}{stderr}")
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn quick_report_has_every_family_with_a_zero_error_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    ok(&matgraph(&["report", "--quick", "--no-gpu", "--out", out]));
    let index = String::from_utf8(read(dir.path(), "README.md")).unwrap();
    for f in FAMILIES {
        assert!(
            index.contains(&format!("[{0}.md]({0}.md)", f.name)),
            "{index}"
        );
        let md = String::from_utf8(read(dir.path(), &format!("{}.md", f.name))).unwrap();
        // The table: header, separator, one row per variant, 11 columns each.
        let rows: Vec<&str> = md.lines().filter(|l| l.starts_with("| ")).collect();
        assert_eq!(rows.len(), 2 + f.variants.len(), "{}:\n{md}", f.name);
        for r in &rows {
            assert_eq!(r.matches(" | ").count(), 10, "{}: {r}", f.name);
        }
        let data: serde_json::Value =
            serde_json::from_slice(&read(dir.path(), &format!("{}.json", f.name))).unwrap();
        let table = data["rows"].as_array().unwrap();
        assert_eq!(table.len(), f.variants.len());
        for (row, v) in table.iter().zip(f.variants) {
            assert_eq!(row["name"], v.name);
            assert!(row["cpu_ns"].as_f64().unwrap() > 0.0, "{row}");
            assert!(row["expressions"].as_u64().unwrap() > 0);
            let is_ref = v.name == f.reference;
            assert_eq!(row["reference"], is_ref);
            let errors = [
                &row["node"]["max"],
                &row["node"]["mean"],
                &row["image"]["rmse"],
                &row["image"]["de_mean"],
                &row["image"]["de_max"],
            ];
            if is_ref {
                assert!(errors.iter().all(|e| e.as_f64() == Some(0.0)), "{row}");
                // Nothing has a smaller error, so the reference is on the front.
                assert_eq!(row["front"], true);
            }
        }
        // Some variant differs from its reference, in both spaces.
        assert!(
            table
                .iter()
                .any(|r| r["node"]["max"].as_f64().unwrap() > 0.0
                    && r["image"]["de_mean"].as_f64().unwrap() > 0.0),
            "{}",
            f.name
        );
        let svg = String::from_utf8(read(dir.path(), &format!("{}.svg", f.name))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains(f.reference));
        let png = image::load_from_memory(&read(dir.path(), &format!("{}.png", f.name))).unwrap();
        assert_eq!((png.width(), png.height()), (720, 480));
    }
}

#[test]
fn untimed_report_is_the_same_bytes_every_run() {
    let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    for d in [&a, &b] {
        let out = d.path().to_str().unwrap();
        ok(&matgraph(&[
            "report",
            "--quick",
            "--no-timing",
            "--family",
            "pbr",
            "--out",
            out,
        ]));
    }
    for name in ["README.md", "pbr.md", "pbr.json", "pbr.svg", "pbr.png"] {
        assert_eq!(read(a.path(), name), read(b.path(), name), "{name}");
    }
    let md = String::from_utf8(read(a.path(), "pbr.md")).unwrap();
    assert!(md.contains("Not timed"), "{md}");
}

/// Without `--out` the report goes to `target/report` under the working folder, so a run on a
/// fresh clone leaves the tracked `docs/report` (regenerated with `--out docs/report`) as it is.
#[test]
fn report_writes_to_target_report_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let graphs = Path::new(env!("CARGO_MANIFEST_DIR")).join("graphs");
    let out = Command::new(env!("CARGO_BIN_EXE_matgraph"))
        .args([
            "report",
            "--quick",
            "--no-timing",
            "--family",
            "pbr",
            "--graphs",
        ])
        .arg(&graphs)
        .current_dir(dir.path())
        .env("XDG_RUNTIME_DIR", "/tmp")
        .output()
        .expect("the binary runs");
    ok(&out);
    let report = dir.path().join("target/report");
    for name in ["README.md", "pbr.md", "pbr.json", "pbr.svg", "pbr.png"] {
        assert!(report.join(name).is_file(), "{name} not in target/report");
    }
    assert!(!dir.path().join("docs").exists(), "docs/ was written");
}

#[test]
fn unknown_family_is_refused_with_the_list() {
    let out = matgraph(&["report", "--family", "marble", "--out", "/nonexistent"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--family marble") && err.contains("cartoon_water"),
        "{err}"
    );
}

/// Exact unpolarised Fresnel reflectance from air into a dielectric of index `n` (Hecht,
/// Optics, eqs. 4.34 and 4.40), in f64.
fn fresnel_exact(cos_i: f64, n: f64) -> f64 {
    let sin_t2 = (1.0 - cos_i * cos_i) / (n * n);
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    let rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Schlick 1994: F0 + (1 − F0)(1 − cos)⁵ with F0 = ((n − 1)/(n + 1))².
fn schlick(cos_i: f64, n: f64) -> f64 {
    let f0 = ((n - 1.0) / (n + 1.0)).powi(2);
    f0 + (1.0 - f0) * (1.0 - cos_i).powi(5)
}

/// The picked choice and the max abs error printed for it.
fn pick(e: f64) -> (String, f64) {
    let out = matgraph(&[
        "eval",
        "graphs/fresnel_variants.json",
        "--max-error",
        &format!("{e}"),
    ]);
    let text = ok(&out);
    let line = text
        .lines()
        .find(|l| l.contains("--max-error: variant fresnel="))
        .unwrap_or_else(|| panic!("{text}"));
    let choice = line
        .split("fresnel=")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap()
        .to_owned();
    let err: f64 = line
        .split("max abs error ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap()
        .parse()
        .unwrap();
    (choice, err)
}

#[test]
fn max_error_picks_schlick_only_when_its_closed_form_error_is_allowed() {
    // The largest |Schlick − exact| at n = 1.52 over cos θ in [0, 1], on a fine grid.
    let n = 1.52;
    let worst = (0..=200_000)
        .map(|k| {
            let c = k as f64 / 200_000.0;
            (schlick(c, n) - fresnel_exact(c, n)).abs()
        })
        .fold(0.0f64, f64::max);
    assert!(worst > 1e-3 && worst < 0.05, "{worst}");
    // Allowed: Schlick (fewer expressions) is picked, and its error, measured at seeded
    // samples of cos θ in [0, 1], is at most the closed form's maximum and close to it.
    let (choice, err) = pick(worst * 1.01);
    assert_eq!(choice, "schlick");
    assert!(
        err <= worst * 1.0001 + 1e-6 && err >= worst * 0.9,
        "{err} vs {worst}"
    );
    // Not allowed: the reference.
    let (choice, err) = pick(worst * 0.5);
    assert_eq!(choice, "exact");
    assert_eq!(err, 0.0);
}

#[test]
fn max_error_without_variants_says_so() {
    let text = ok(&matgraph(&[
        "wgsl",
        "graphs/fresnel_glass.json",
        "--max-error",
        "0.01",
    ]));
    assert!(text.contains("declares no variants"), "{text}");
}

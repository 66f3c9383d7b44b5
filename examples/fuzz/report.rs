//! Running many cases on all cores, and what a run found: findings by message (with their
//! reproducers written to a folder), known signatures, cases per family, per-case wall
//! time (the slowest case and how many took over a second), and the cases over a second
//! run again alone, so that a case stretched by other work on the machine is told from a
//! slow one.

use super::cases::{Corpus, Family};
use super::stages::run_case;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::panic::catch_unwind;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A case slower than this is a finding: 1 s in release builds (the bound), 30 s
/// in debug builds (the CI slice), which run the library some 20 times slower.
pub const SLOW_SECONDS: f64 = if cfg!(debug_assertions) { 30.0 } else { 1.0 };

/// No case yet.
const SLOWEST_NONE: (f64, u64, Option<Family>) = (0.0, 0, None);

/// At most this many reproducers are written per distinct message.
const KEEP: usize = 5;

/// The outcome of a run.
#[derive(Debug, Default)]
pub struct Report {
    /// The run's seed.
    pub seed: u64,
    /// Cases run.
    pub cases: u64,
    /// Seconds taken.
    pub seconds: f64,
    /// Findings by `stage: message`: how many, and the first few case numbers.
    pub findings: BTreeMap<String, (u64, Vec<u64>)>,
    /// Known signatures matched (not findings), by signature: how many, first cases.
    pub known: BTreeMap<String, (u64, Vec<u64>)>,
    /// Cases run per family.
    pub families: BTreeMap<Family, u64>,
    /// The slowest case: seconds, case number, family.
    pub slowest: (f64, u64, Option<Family>),
    /// Every case over [`SLOW_SECONDS`] in the run: case number, family, its wall time in
    /// the run and the fastest of [`REPLAYS`] runs alone afterwards (seconds).
    pub slow: Vec<(u64, Family, f64, f64)>,
}

/// How many times a case over [`SLOW_SECONDS`] is run again alone after the run.
pub const REPLAYS: usize = 3;

impl Report {
    /// Cases per second.
    pub fn rate(&self) -> f64 {
        self.cases as f64 / self.seconds.max(1e-9)
    }

    /// The report as text: counts, rate, slowest case, findings.
    pub fn summary(&self) -> String {
        let mut s = format!(
            "{} cases (seed {}) in {:.1} s: {:.0} cases/s on {} threads\n",
            self.cases,
            self.seed,
            self.seconds,
            self.rate(),
            rayon::current_num_threads()
        );
        let fam: Vec<String> = self
            .families
            .iter()
            .map(|(f, n)| format!("{} {n}", f.name()))
            .collect();
        s += &format!("families: {}\n", fam.join(", "));
        let (secs, case, family) = self.slowest;
        s += &format!(
            "slowest case: {:.3} s, case {case} ({}; replay with --seed {} --case {case})\n",
            secs,
            family.map_or("-", Family::name),
            self.seed
        );
        let alone = self.slow.iter().filter(|c| c.3 > SLOW_SECONDS).count();
        s += &format!(
            "cases over {SLOW_SECONDS} s: {} in the run; {alone} of them over {SLOW_SECONDS} s alone (fastest of {REPLAYS})\n",
            self.slow.len()
        );
        for (case, family, wall, min) in &self.slow {
            s += &format!(
                "  case {case} ({}): {wall:.3} s in the run, {min:.3} s alone\n",
                family.name()
            );
        }
        s += &format!("findings: {} distinct\n", self.findings.len());
        for (message, (count, cases)) in &self.findings {
            s += &format!("  {count} × {message} (cases {cases:?})\n");
        }
        for (message, (count, cases)) in &self.known {
            s += &format!("known, not counted: {count} × {message} (cases {cases:?})\n");
        }
        s
    }
}

/// Records one case's finding (or known signature) in `map`, writing its reproducer to
/// `out` when it is among the first few of its message.
fn record(
    map: &Mutex<BTreeMap<String, (u64, Vec<u64>)>>,
    key: String,
    case: u64,
    reproducer: impl FnOnce() -> (String, String),
    out: Option<&Path>,
    prefix: &str,
) {
    let mut m = map.lock().unwrap_or_else(|e| e.into_inner());
    let entry = m.entry(key).or_default();
    entry.0 += 1;
    if entry.1.len() < KEEP {
        entry.1.push(case);
        if let Some(dir) = out {
            let (json, txt) = reproducer();
            let _ = std::fs::create_dir_all(dir);
            let base = dir.join(format!("{prefix}-{case}"));
            let _ = std::fs::write(base.with_extension("json"), json);
            let _ = std::fs::write(base.with_extension("txt"), txt);
        }
    }
}

/// What [`run`] runs, besides the corpus and the seed.
#[derive(Clone, Debug, Default)]
pub struct RunOptions<'a> {
    /// The first case number.
    pub first: u64,
    /// How many cases (`first..first + cases`).
    pub cases: u64,
    /// Where findings are written (`<stage>-<case>.json`, replayable with `--replay`, and a
    /// `.txt` with the message), at most 5 per distinct message.
    pub out: Option<&'a Path>,
    /// Every this many cases a line goes to stderr (0: never).
    pub progress: u64,
    /// Only this family's cases run; the others are skipped (not counted).
    pub only: Option<Family>,
    /// Cases not started by this many seconds are skipped (the report counts what ran).
    pub max_seconds: Option<f64>,
}

/// Runs the cases of run `seed` that `options` names on all threads.
pub fn run(corpus: &Corpus, seed: u64, options: &RunOptions) -> Report {
    let RunOptions {
        first,
        cases,
        out,
        progress,
        only,
        max_seconds,
    } = options.clone();
    let findings = Mutex::new(BTreeMap::new());
    let known = Mutex::new(BTreeMap::new());
    let stats = Mutex::new((BTreeMap::<Family, u64>::new(), SLOWEST_NONE));
    let done = AtomicU64::new(0);
    let slow_in_run = Mutex::new(Vec::<(u64, Family, f64)>::new());
    let start = Instant::now();
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {})); // panics are caught and reported per case
    (first..first + cases).into_par_iter().for_each(|case| {
        if max_seconds.is_some_and(|m| start.elapsed().as_secs_f64() > m) {
            return;
        }
        let t = Instant::now();
        let Ok(c) = catch_unwind(|| corpus.case(seed, case)) else {
            record(
                &findings,
                "mutate: the fuzzer itself panicked".into(),
                case,
                || (String::new(), format!("seed {seed} case {case}\n")),
                out,
                "mutate",
            );
            return;
        };
        if only.is_some_and(|f| f != c.family) {
            return;
        }
        let outcome = run_case(&c);
        let secs = t.elapsed().as_secs_f64();
        if let Some(f) = outcome.finding {
            let key = format!("{}: {}", f.stage, f.message.lines().next().unwrap_or(""));
            let txt = format!("seed {seed} case {case}\n{}\n", f.message);
            record(
                &findings,
                key,
                case,
                || (c.to_json(seed, case), txt),
                out,
                f.stage,
            );
        }
        if let Some(k) = outcome.known {
            record(
                &known,
                k.to_owned(),
                case,
                || (String::new(), String::new()),
                None,
                "",
            );
        }
        {
            let mut s = stats.lock().unwrap_or_else(|e| e.into_inner());
            *s.0.entry(c.family).or_default() += 1;
            if secs > s.1.0 {
                s.1 = (secs, case, Some(c.family));
            }
        }
        if secs > SLOW_SECONDS {
            slow_in_run
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push((case, c.family, secs));
            if let Some(dir) = out {
                let _ = std::fs::create_dir_all(dir);
                let line = format!("{case} {} {secs:.3}\n", c.family.name());
                let _ = std::fs::OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(dir.join("slow-cases.txt"))
                    .and_then(|mut f| std::io::Write::write_all(&mut f, line.as_bytes()));
            }
        }
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        if progress > 0 && n.is_multiple_of(progress) {
            let e = start.elapsed().as_secs_f64();
            let f = findings.lock().map(|m| m.len()).unwrap_or(0);
            let slow = stats.lock().map(|s| s.1).unwrap_or(SLOWEST_NONE);
            let over = slow_in_run.lock().map(|v| v.len()).unwrap_or(0);
            eprintln!(
                "{n} cases, {e:.0} s, {:.0} cases/s, {f} distinct findings, slowest {:.3} s (case {}), {over} over {SLOW_SECONDS} s",
                n as f64 / e,
                slow.0,
                slow.1
            );
        }
    });
    let seconds = start.elapsed().as_secs_f64();
    // Each case over the bound, run again alone (nothing else running in this process):
    // the fastest of the replays is its own time; over the bound, it is a finding.
    let mut in_run = slow_in_run.into_inner().unwrap_or_else(|e| e.into_inner());
    in_run.sort_by_key(|c| c.0);
    let mut slow = Vec::with_capacity(in_run.len());
    for (case, family, wall) in in_run {
        let c = corpus.case(seed, case);
        let alone = (0..REPLAYS)
            .map(|_| {
                let t = Instant::now();
                let _ = catch_unwind(|| run_case(&c));
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min);
        if alone > SLOW_SECONDS {
            let txt = format!(
                "seed {seed} case {case}\ntook {wall:.3} s in the run, {alone:.3} s alone\n"
            );
            record(
                &findings,
                format!(
                    "slow: a {} case took over {SLOW_SECONDS} s alone",
                    family.name()
                ),
                case,
                || (c.to_json(seed, case), txt),
                out,
                "slow",
            );
        }
        slow.push((case, family, wall, alone));
    }
    std::panic::set_hook(previous);
    let (families, slowest) = stats.into_inner().unwrap_or_else(|e| e.into_inner());
    Report {
        seed,
        cases: families.values().sum(),
        seconds,
        findings: findings.into_inner().unwrap_or_else(|e| e.into_inner()),
        known: known.into_inner().unwrap_or_else(|e| e.into_inner()),
        families,
        slowest,
        slow,
    }
}

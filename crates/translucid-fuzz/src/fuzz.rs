//! The fuzzing loop: parallel jobs draw case numbers, build each mutant beside a copy of its
//! seed's folder, run it in a child, and record the outcome until time is up.

use crate::corpus::{self, Seed};
use crate::mutate::{self, Mutant};
use crate::report::{Case, Report};
use crate::rng::Rng;
use crate::runner::{self, Limits, Outcome};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

pub struct Options {
    pub seconds: u64,
    /// Run cases 0 to N-1, ignoring `seconds`.
    pub cases: Option<u64>,
    pub seed: u64,
    pub corpus: Vec<PathBuf>,
    pub out: PathBuf,
    pub jobs: usize,
    pub limits: Limits,
    /// Run only this case (to reproduce a finding).
    pub case: Option<u64>,
    /// Where the jobs' work folders go (removed at the end).
    pub work: PathBuf,
}

/// Runs the fuzzer; returns whether anything was found.
pub fn run(options: &Options) -> Result<bool, String> {
    let seeds = corpus::load(&options.corpus)?;
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let _ = std::fs::remove_dir_all(&options.work);
    let result = match options.case {
        Some(case) => replay(options, &seeds, &exe, case),
        None => fuzz(options, &seeds, &exe),
    };
    let _ = std::fs::remove_dir_all(&options.work);
    result
}

/// Copies of seed folders, one set per job, made on first use.
struct WorkDir {
    root: PathBuf,
    copies: HashMap<PathBuf, PathBuf>,
}

impl WorkDir {
    fn new(root: PathBuf) -> Self {
        Self {
            root,
            copies: HashMap::new(),
        }
    }

    /// The job's copy of `seed`'s folder: the mutant is written into it, so that relative
    /// URIs resolve to the seed's files (or their mutated versions).
    fn folder(&mut self, seed: &Seed) -> std::io::Result<PathBuf> {
        if let Some(dir) = self.copies.get(&seed.dir) {
            return Ok(dir.clone());
        }
        let dir = self.root.join(format!("folder-{}", self.copies.len()));
        std::fs::create_dir_all(&dir)?;
        for rel in &seed.copies {
            let to = dir.join(rel);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent)?;
            }
            std::fs::copy(seed.dir.join(rel), to)?;
        }
        self.copies.insert(seed.dir.clone(), dir.clone());
        Ok(dir)
    }
}

/// Writes the mutant into its folder, runs it, records it, and puts the seed's files back.
fn run_case(
    options: &Options,
    seeds: &[Seed],
    exe: &Path,
    work: &mut WorkDir,
    number: u64,
    report: &Mutex<Report>,
) -> Result<(Outcome, Option<PathBuf>), String> {
    let mutant = mutate::make(seeds, &mut Rng::for_case(options.seed, number));
    let seed = &seeds[mutant.seed];
    let io = |e: std::io::Error| format!("case {number}: work folder: {e}");
    let dir = work.folder(seed).map_err(io)?;
    let main = dir.join(mutant.file_name());
    std::fs::write(&main, &mutant.main).map_err(io)?;
    for (rel, bytes) in &mutant.overrides {
        std::fs::write(dir.join(rel), bytes).map_err(io)?;
    }
    let outcome = runner::run(exe, &main, options.limits)
        .map_err(|e| format!("case {number}: cannot run the child: {e}"))?;
    let description = mutant.describe();
    let case = Case {
        seed: options.seed,
        number,
        mutant: &description,
        replay: replay_command(options, number),
        files: files_of(&mutant, seed, &dir),
        main_file: mutant.file_name(),
    };
    let saved = report
        .lock()
        .map_err(|_| "a job panicked".to_string())?
        .record(&outcome, &case, &options.out);
    restore(&mutant, seed, &dir).map_err(io)?;
    Ok((outcome, saved))
}

/// The mutant and the files it may reference: what a finding's folder needs to load alone.
fn files_of(mutant: &Mutant, seed: &Seed, dir: &Path) -> Vec<(PathBuf, PathBuf)> {
    let main = PathBuf::from(mutant.file_name());
    let mut files = vec![(main.clone(), dir.join(&main))];
    files.extend(
        seed.siblings
            .iter()
            .map(|s| (s.rel.clone(), dir.join(&s.rel))),
    );
    files
}

fn restore(mutant: &Mutant, seed: &Seed, dir: &Path) -> std::io::Result<()> {
    for (rel, _) in &mutant.overrides {
        if let Some(original) = seed.siblings.iter().find(|s| &s.rel == rel) {
            std::fs::write(dir.join(rel), &original.bytes)?;
        }
    }
    Ok(())
}

fn replay_command(options: &Options, number: u64) -> String {
    let corpus: Vec<String> = options
        .corpus
        .iter()
        .map(|c| format!("--corpus {}", c.display()))
        .collect();
    format!(
        "translucid-fuzz gltf --seed {} --case {number} {}",
        options.seed,
        corpus.join(" ")
    )
}

fn fuzz(options: &Options, seeds: &[Seed], exe: &Path) -> Result<bool, String> {
    let length = match options.cases {
        Some(cases) => format!("{cases} cases"),
        None => format!("{} s", options.seconds),
    };
    eprintln!(
        "fuzzing glTF import: {} seeds, seed {}, {} jobs, {length}, child limits {} s and {} MiB; findings go to {}",
        seeds.len(),
        options.seed,
        options.jobs,
        options.limits.timeout.as_secs(),
        options.limits.memory >> 20,
        options.out.display()
    );
    let start = Instant::now();
    let deadline = match options.cases {
        // Long enough never to come.
        Some(_) => start + Duration::from_secs(100 * 365 * 86_400),
        None => start + Duration::from_secs(options.seconds),
    };
    let next = AtomicU64::new(0);
    let report = Mutex::new(Report::default());
    let failure: Mutex<Option<String>> = Mutex::new(None);
    let jobs = options.jobs.max(1);
    // Jobs still drawing cases: progress reports stop with the last.
    let running = AtomicUsize::new(jobs);
    std::thread::scope(|scope| {
        for job in 0..jobs {
            let (next, report, failure, running) = (&next, &report, &failure, &running);
            scope.spawn(move || {
                let mut work = WorkDir::new(options.work.join(format!("job-{job}")));
                while Instant::now() < deadline {
                    let number = next.fetch_add(1, Ordering::Relaxed);
                    if options.cases.is_some_and(|cases| number >= cases) {
                        break;
                    }
                    match run_case(options, seeds, exe, &mut work, number, report) {
                        Ok((_, Some(dir))) => {
                            eprintln!("finding: case {number} -> {}", dir.display())
                        }
                        Ok((Outcome::Finding(f), None)) => eprintln!(
                            "finding: case {number} ({}; not saved: its cause has enough examples)",
                            f.kind.name()
                        ),
                        Ok(_) => {}
                        Err(e) => {
                            if let Ok(mut slot) = failure.lock() {
                                slot.get_or_insert(e);
                            }
                            break;
                        }
                    }
                    if failure.lock().map_or(true, |f| f.is_some()) {
                        break;
                    }
                }
                running.fetch_sub(1, Ordering::Relaxed);
            });
        }
        // Progress every 30 s, so that a long run shows it is alive.
        scope.spawn(|| {
            let mut last = Instant::now();
            while Instant::now() < deadline
                && running.load(Ordering::Relaxed) > 0
                && failure.lock().is_ok_and(|f| f.is_none())
            {
                std::thread::sleep(Duration::from_millis(200));
                if last.elapsed() >= Duration::from_secs(30) {
                    last = Instant::now();
                    if let Ok(r) = report.lock() {
                        eprintln!(
                            "[{:.0} s] {}",
                            start.elapsed().as_secs_f64(),
                            r.summary(start.elapsed().as_secs_f64())
                        );
                    }
                }
            }
        });
    });
    if let Some(e) = failure.into_inner().ok().flatten() {
        return Err(e);
    }
    let report = report
        .into_inner()
        .map_err(|_| "a job panicked".to_string())?;
    let causes = report.causes();
    if !causes.is_empty() {
        println!("distinct causes:\n{causes}");
    }
    println!("{}", report.summary(start.elapsed().as_secs_f64()));
    Ok(report.findings() > 0)
}

/// Rebuilds and runs one case and prints its outcome; a finding is saved the usual way.
fn replay(options: &Options, seeds: &[Seed], exe: &Path, number: u64) -> Result<bool, String> {
    let report = Mutex::new(Report::default());
    let mut work = WorkDir::new(options.work.join("replay"));
    let (outcome, saved) = run_case(options, seeds, exe, &mut work, number, &report)?;
    let mutant = mutate::make(seeds, &mut Rng::for_case(options.seed, number));
    println!("case {number}: {}", mutant.describe());
    let found = match &outcome {
        Outcome::Loaded => {
            println!("outcome: loaded");
            false
        }
        Outcome::CleanError => {
            println!("outcome: clean error");
            false
        }
        Outcome::Finding(f) => {
            println!("outcome: {} ({})\n{}", f.kind.name(), f.status, f.stderr);
            true
        }
    };
    if let Some(dir) = saved {
        println!("saved to {}", dir.display());
    }
    Ok(found)
}

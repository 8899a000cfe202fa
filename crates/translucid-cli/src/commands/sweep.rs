//! `bench --sweep`: how each method's cost grows with a frame's triangles or pixels. Every
//! point is a bench of its own (the methods taking turns, blend among them); the GPU time of
//! each method's stages is fitted on log-log axes, whose slope says how the cost grows (1:
//! in proportion), and plotted, one line per method.

use super::bench::{measure, Bench, Measured};
use crate::{Size, Sweep, SweepOver};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The scenes a sweep over triangles takes: cut into as many triangles as a point asks.
const TRIANGLE_SCENES: &[&str] = &["hairball", "particles"];

/// One method's times along the sweep over one scene.
struct Series {
    scene: String,
    method: String,
    /// (point, what the slope is over: triangles or pixels, GPU ms, wall ms)
    points: Vec<(u64, f64, f64, f64)>,
}

impl Series {
    /// The least-squares slope of ln(GPU ms) over ln(x); NaN when some time is not positive.
    fn slope(&self) -> f64 {
        let logs: Vec<(f64, f64)> = self
            .points
            .iter()
            .map(|&(_, x, ms, _)| (x.ln(), ms.ln()))
            .collect();
        if logs.iter().any(|(x, y)| !x.is_finite() || !y.is_finite()) {
            return f64::NAN;
        }
        let n = logs.len() as f64;
        let (mx, my) = (
            logs.iter().map(|l| l.0).sum::<f64>() / n,
            logs.iter().map(|l| l.1).sum::<f64>() / n,
        );
        let cov: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
        let var: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
        cov / var
    }
}

pub fn run(
    scenes: &[String],
    bench: &Bench<'_>,
    sweep: &Sweep,
    plot: &Path,
    json: bool,
) -> translucid::Result<ExitCode> {
    let refuse = |why: String| {
        eprintln!("translucid: {why}");
        Ok(ExitCode::FAILURE)
    };
    if sweep.over == SweepOver::Triangles {
        if let Some(bad) = scenes
            .iter()
            .find(|s| !TRIANGLE_SCENES.contains(&s.as_str()))
        {
            return refuse(format!(
                "--sweep triangles takes the scenes cut into a given number of triangles ({}), \
                 not {bad:?}",
                TRIANGLE_SCENES.join(", ")
            ));
        }
    }
    let mut measured: Vec<(u64, f64, Vec<Measured>)> = Vec::new();
    for &point in &sweep.points {
        let (specs, size, x) = match sweep.over {
            SweepOver::Triangles => (
                scenes.iter().map(|s| format!("{s}:{point}")).collect(),
                bench.frame_loop.size,
                point as f64,
            ),
            SweepOver::Size => {
                let Ok(side) = u32::try_from(point) else {
                    return refuse(format!("--sweep size: a {point}-pixel side"));
                };
                let size = Size {
                    width: side,
                    height: side,
                };
                (scenes.to_vec(), size, (point * point) as f64)
            }
        };
        if !json {
            eprintln!("sweep point {point}: {}x{}", size.width, size.height);
        }
        measured.push((point, x, measure(&specs, bench, size)?));
    }
    let motion = bench.frame_loop.motion.first().copied();
    let mut names = vec!["blend".to_string()];
    names.extend(bench.methods.iter().filter(|m| *m != "blend").cloned());
    let over = match sweep.over {
        SweepOver::Triangles => "triangles",
        SweepOver::Size => "size",
    };
    for (k, scene) in scenes.iter().enumerate() {
        let series: Vec<Series> = names
            .iter()
            .map(|method| Series {
                scene: scene.clone(),
                method: method.clone(),
                points: measured
                    .iter()
                    .filter_map(|(point, x, results)| {
                        // A point's results are per spec, in the order of `scenes`.
                        let spec = match sweep.over {
                            SweepOver::Triangles => format!("{scene}:{point}"),
                            SweepOver::Size => scene.clone(),
                        };
                        results
                            .iter()
                            .find(|r| {
                                r.scene == spec && &r.method == method && Some(r.motion) == motion
                            })
                            .map(|r| (*point, *x, r.method_ms, r.wall_ms))
                    })
                    .collect(),
            })
            .collect();
        let path = plot_path(plot, scene, scenes.len(), k);
        if let Err(why) = write_plot(&path, &series, sweep.over) {
            return refuse(format!("cannot write the plot {}: {why}", path.display()));
        }
        if json {
            for s in &series {
                let points: Vec<serde_json::Value> = s
                    .points
                    .iter()
                    .map(|&(point, x, ms, wall)| {
                        serde_json::json!({"point": point, "x": x, "method_ms": ms, "wall_ms": wall})
                    })
                    .collect();
                let line = serde_json::json!({
                    "sweep": over,
                    "scene": s.scene,
                    "method": s.method,
                    "points": points,
                    "slope": s.slope(),
                    "plot": path.display().to_string(),
                });
                println!("{line}");
            }
        } else {
            print_table(&series, sweep.over, &path);
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Where the plot of the `k`th of `count` scenes goes: `plot` itself for one scene, else with
/// the scene's name before its extension.
fn plot_path(plot: &Path, scene: &str, count: usize, k: usize) -> PathBuf {
    if count == 1 {
        return plot.to_path_buf();
    }
    let stem = plot
        .file_stem()
        .map_or_else(|| format!("sweep{k}"), |s| s.to_string_lossy().into_owned());
    let name: String = Path::new(scene)
        .file_stem()
        .map_or_else(|| format!("{k}"), |s| s.to_string_lossy().into_owned());
    plot.with_file_name(format!("{stem}-{name}.svg"))
}

fn print_table(series: &[Series], over: SweepOver, plot: &Path) {
    let Some(first) = series.first() else {
        return;
    };
    let unit = match over {
        SweepOver::Triangles => "triangles",
        SweepOver::Size => "side (px)",
    };
    println!(
        "{}: GPU ms of each method's stages (frame wall ms in brackets)",
        first.scene
    );
    print!("  {unit:<20}");
    for s in series {
        print!(" {:>22}", s.method);
    }
    println!();
    for (i, &(point, ..)) in first.points.iter().enumerate() {
        print!("  {point:<20}");
        for s in series {
            match s.points.get(i) {
                Some(&(_, _, ms, wall)) => print!(" {:>22}", format!("{ms:.3} ({wall:.1})")),
                None => print!(" {:>22}", "-"),
            }
        }
        println!();
    }
    let slope_of = match over {
        SweepOver::Triangles => "slope over triangles",
        SweepOver::Size => "slope over pixels",
    };
    print!("  {slope_of:<20}");
    for s in series {
        print!(" {:>22}", format!("{:.2}", s.slope()));
    }
    println!();
    println!("  wrote {}", plot.display());
}

/// GPU ms against triangles or pixels on log-log axes, one line per method (SVG).
fn write_plot(path: &Path, series: &[Series], over: SweepOver) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    }
    let all = series.iter().flat_map(|s| s.points.iter());
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(_, x, ms, _) in all {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
        y_lo = y_lo.min(ms.max(1e-3));
        y_hi = y_hi.max(ms.max(1e-3));
    }
    if x_lo >= x_hi || y_lo > y_hi {
        return Err("no two points to plot".into());
    }
    let x_desc = match over {
        SweepOver::Triangles => "transparent triangles",
        SweepOver::Size => "pixels",
    };
    let title = series.first().map_or("", |s| s.scene.as_str());
    let root = SVGBackend::new(path, (800, 560)).into_drawing_area();
    let draw = |root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>| {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(root)
            .caption(format!("{title}: GPU ms per frame"), ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(
                (x_lo * 0.9..x_hi * 1.1).log_scale(),
                (y_lo * 0.8..y_hi * 1.25).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("ms (log)")
            .draw()?;
        for (i, s) in series.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let line: Vec<(f64, f64)> = s.points.iter().map(|p| (p.1, p.2.max(1e-3))).collect();
            chart
                .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))?
                .label(format!("{} (slope {:.2})", s.method, s.slope()))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
            chart.draw_series(line.into_iter().map(|p| Circle::new(p, 3, colour.filled())))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        root.present()
    };
    draw(&root).map_err(|e| e.to_string())
}

//! Where a sweep's results go: a folder with the sweep file as run (`sweep.toml`, and the scene
//! it starts from), the rows as Parquet files `runs/part-NNNNNN.parquet` written as runs finish
//! (each a complete file, written under a temporary name and renamed, so an interruption never
//! leaves a broken one), on request `runs.csv`, and the plots. Reading `runs/` as one Parquet
//! dataset (pandas `read_parquet("…/runs")`, pyarrow, Dask, DuckDB, Polars) gives every row.
//!
//! Columns: `run` (0-based, the run's number in the design), the swept parameters (SI, the
//! speed in rpm), the metrics (null for a run without metrics), `warnings` (how many the model
//! logged), `warning` (the first, null if none), `error` (why the run has no metrics, null if it
//! ran).
//!
//! An interrupted sweep resumes: [`Store::open`] reads the finished runs from the parts, and
//! refuses a folder whose sweep file differs from the one given (its results would mix two
//! sweeps).

use super::{Plan, Row};
use parquet::basic::{ConvertedType, Repetition, Type as Physical};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::file::writer::SerializedFileWriter;
use parquet::record::Field;
use parquet::schema::types::Type;
use std::collections::BTreeSet;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A part is written after this many rows, or this long after the previous one.
const PART_ROWS: usize = 5000;
const PART_EVERY: Duration = Duration::from_secs(2);

/// The results folder of a sweep being run.
pub struct Store {
    dir: PathBuf,
    params: Vec<String>,
    metrics: Vec<String>,
    pending: Vec<Row>,
    next_part: usize,
    csv: Option<fs::File>,
    last: Instant,
}

fn err<E: std::fmt::Display>(what: &Path) -> impl Fn(E) -> String + '_ {
    move |e| format!("{}: {e}", what.display())
}

/// The folder of the part files in a results folder.
pub const RUNS: &str = "runs";

/// The part files of a results folder, in order.
fn parts(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let dir = dir.join(RUNS);
    if !dir.exists() {
        return Ok(Vec::new());
    }
    let mut out: Vec<PathBuf> = fs::read_dir(&dir)
        .map_err(err(&dir))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("part-") && n.ends_with(".parquet"))
        })
        .collect();
    out.sort();
    Ok(out)
}

impl Store {
    /// Opens (or creates) the results folder `dir` of `plan`; with `fresh`, results of an
    /// earlier run of another sweep there are deleted, else refused. Returns the store and the
    /// runs already done. With `csv`, `runs.csv` is (re)written from the parts and then grows
    /// with them.
    pub fn open(
        dir: &Path,
        plan: &Plan,
        fresh: bool,
        csv: bool,
    ) -> Result<(Store, BTreeSet<usize>), String> {
        let runs = dir.join(RUNS);
        fs::create_dir_all(&runs).map_err(err(&runs))?;
        let file = dir.join("sweep.toml");
        let scene = dir.join("scene.toml");
        let same = fs::read_to_string(&file).ok().as_deref() == Some(plan.text.as_str())
            && fs::read_to_string(&scene).ok() == plan.scene;
        let old = parts(dir)?;
        if !same && (!old.is_empty() || file.exists()) {
            if !fresh {
                return Err(format!(
                    "{} holds the results of another sweep file (its sweep.toml differs from this one): \
                     give --fresh to replace them, or --out another folder",
                    dir.display()
                ));
            }
            for p in &old {
                fs::remove_file(p).map_err(err(p))?;
            }
            let _ = fs::remove_file(dir.join("runs.csv"));
        }
        if fresh && same {
            for p in &old {
                fs::remove_file(p).map_err(err(p))?;
            }
            let _ = fs::remove_file(dir.join("runs.csv"));
        }
        fs::write(&file, &plan.text).map_err(err(&file))?;
        match &plan.scene {
            Some(s) => fs::write(&scene, s).map_err(err(&scene))?,
            None => {
                let _ = fs::remove_file(&scene);
            }
        }
        let params: Vec<String> = plan.swept.iter().map(|s| s.name.clone()).collect();
        let metrics: Vec<String> = plan.metrics.iter().map(|m| m.name.clone()).collect();
        let rows = read(dir)?;
        let done: BTreeSet<usize> = rows.iter().map(|r| r.run).collect();
        let next_part = parts(dir)?
            .last()
            .and_then(|p| {
                p.file_stem()?
                    .to_str()?
                    .strip_prefix("part-")?
                    .parse::<usize>()
                    .ok()
            })
            .map_or(0, |n| n + 1);
        let csv = if csv {
            let path = dir.join("runs.csv");
            let mut f = fs::File::create(&path).map_err(err(&path))?;
            let mut all = rows;
            all.sort_by_key(|r| r.run);
            let mut text = csv_header(&params, &metrics);
            for r in &all {
                text.push_str(&csv_line(r, metrics.len()));
            }
            f.write_all(text.as_bytes()).map_err(err(&path))?;
            Some(f)
        } else {
            None
        };
        Ok((
            Store {
                dir: dir.to_path_buf(),
                params,
                metrics,
                pending: Vec::new(),
                next_part,
                csv,
                last: Instant::now(),
            },
            done,
        ))
    }

    /// Adds a finished run; writes a part when enough have gathered.
    pub fn push(&mut self, row: Row) -> Result<(), String> {
        self.pending.push(row);
        if self.pending.len() >= PART_ROWS || self.last.elapsed() >= PART_EVERY {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes the gathered runs as the next part (and to `runs.csv`).
    pub fn flush(&mut self) -> Result<(), String> {
        self.last = Instant::now();
        if self.pending.is_empty() {
            return Ok(());
        }
        let name = format!("part-{:06}.parquet", self.next_part);
        let tmp = self.dir.join(RUNS).join(format!(".{name}.tmp"));
        let path = self.dir.join(RUNS).join(&name);
        let bytes = to_parquet(&self.params, &self.metrics, &self.pending)?;
        fs::write(&tmp, bytes).map_err(err(&tmp))?;
        fs::rename(&tmp, &path).map_err(err(&path))?;
        if let Some(f) = &mut self.csv {
            let text: String = (self.pending.iter())
                .map(|r| csv_line(r, self.metrics.len()))
                .collect();
            f.write_all(text.as_bytes())
                .map_err(err(&self.dir.join("runs.csv")))?;
        }
        self.next_part += 1;
        self.pending.clear();
        Ok(())
    }
}

/// The rows of a results folder, in the order of its parts.
pub fn read(dir: &Path) -> Result<Vec<Row>, String> {
    let mut out = Vec::new();
    for p in parts(dir)? {
        out.extend(from_parquet(&p)?);
    }
    Ok(out)
}

fn csv_header(params: &[String], metrics: &[String]) -> String {
    let mut h = vec!["run".to_string()];
    h.extend(params.iter().chain(metrics).map(|c| csv_text(c)));
    h.extend(["warnings", "warning", "error"].map(String::from));
    h.join(",") + "\n"
}

/// A CSV field: quoted if it holds a comma, quote or line break.
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn csv_line(r: &Row, metrics: usize) -> String {
    let mut f = vec![r.run.to_string()];
    f.extend(r.params.iter().map(|x| format!("{x:?}")));
    if r.metrics.is_empty() {
        f.extend(std::iter::repeat_n(String::new(), metrics));
    } else {
        f.extend(r.metrics.iter().map(|x| format!("{x:?}")));
    }
    f.push(r.warnings.to_string());
    f.push(csv_text(&r.warning));
    f.push(csv_text(&r.error));
    f.join(",") + "\n"
}

fn pq<E: std::fmt::Display>(e: E) -> String {
    format!("Parquet: {e}")
}

/// The rows as one Parquet file (one row group, uncompressed).
fn to_parquet(params: &[String], metrics: &[String], rows: &[Row]) -> Result<Vec<u8>, String> {
    let col = |name: &str, ty: Physical, rep: Repetition| {
        Arc::new(
            Type::primitive_type_builder(name, ty)
                .with_repetition(rep)
                .build()
                .expect("a valid column"),
        )
    };
    let text = |name: &str| {
        Arc::new(
            Type::primitive_type_builder(name, Physical::BYTE_ARRAY)
                .with_repetition(Repetition::OPTIONAL)
                .with_converted_type(ConvertedType::UTF8)
                .build()
                .expect("a valid column"),
        )
    };
    let mut fields = vec![col("run", Physical::INT64, Repetition::REQUIRED)];
    fields.extend(
        params
            .iter()
            .map(|p| col(p, Physical::DOUBLE, Repetition::REQUIRED)),
    );
    fields.extend(
        metrics
            .iter()
            .map(|m| col(m, Physical::DOUBLE, Repetition::OPTIONAL)),
    );
    fields.push(col("warnings", Physical::INT64, Repetition::REQUIRED));
    fields.push(text("warning"));
    fields.push(text("error"));
    let schema = Arc::new(
        Type::group_type_builder("sweep")
            .with_fields(fields)
            .build()
            .map_err(pq)?,
    );
    let props = Arc::new(
        WriterProperties::builder()
            .set_created_by("bindery sweep".into())
            .build(),
    );
    let mut out = Vec::new();
    let mut w = SerializedFileWriter::new(&mut out, schema, props).map_err(pq)?;
    let mut g = w.next_row_group().map_err(pq)?;
    let mut column = 0usize;
    while let Some(mut c) = g.next_column().map_err(pq)? {
        let np = params.len();
        let nm = metrics.len();
        match column {
            0 => {
                let v: Vec<i64> = rows.iter().map(|r| r.run as i64).collect();
                c.typed::<Int64Type>()
                    .write_batch(&v, None, None)
                    .map_err(pq)?;
            }
            k if k <= np => {
                let v: Vec<f64> = rows.iter().map(|r| r.params[k - 1]).collect();
                c.typed::<DoubleType>()
                    .write_batch(&v, None, None)
                    .map_err(pq)?;
            }
            k if k <= np + nm => {
                let i = k - 1 - np;
                let v: Vec<f64> = rows
                    .iter()
                    .filter_map(|r| r.metrics.get(i).copied())
                    .collect();
                let def: Vec<i16> = rows
                    .iter()
                    .map(|r| i16::from(!r.metrics.is_empty()))
                    .collect();
                c.typed::<DoubleType>()
                    .write_batch(&v, Some(&def), None)
                    .map_err(pq)?;
            }
            k if k == np + nm + 1 => {
                let v: Vec<i64> = rows.iter().map(|r| r.warnings as i64).collect();
                c.typed::<Int64Type>()
                    .write_batch(&v, None, None)
                    .map_err(pq)?;
            }
            k => {
                let of = |r: &Row| {
                    if k == np + nm + 2 {
                        r.warning.clone()
                    } else {
                        r.error.clone()
                    }
                };
                let v: Vec<ByteArray> = (rows.iter().map(of))
                    .filter(|s| !s.is_empty())
                    .map(|s| ByteArray::from(s.into_bytes()))
                    .collect();
                let def: Vec<i16> = rows.iter().map(|r| i16::from(!of(r).is_empty())).collect();
                c.typed::<ByteArrayType>()
                    .write_batch(&v, Some(&def), None)
                    .map_err(pq)?;
            }
        }
        c.close().map_err(pq)?;
        column += 1;
    }
    g.close().map_err(pq)?;
    w.close().map_err(pq)?;
    Ok(out)
}

/// The rows of one part file.
fn from_parquet(path: &Path) -> Result<Vec<Row>, String> {
    let e = |x: String| format!("{}: {x}", path.display());
    let f = fs::File::open(path).map_err(|x| e(x.to_string()))?;
    let r = SerializedFileReader::new(f).map_err(|x| e(pq(x)))?;
    let names: Vec<String> = (r.metadata().file_metadata().schema_descr().columns().iter())
        .map(|c| c.name().to_string())
        .collect();
    let n = names.len();
    if n < 4 || names[0] != "run" || names[n - 3..] != ["warnings", "warning", "error"] {
        return Err(e("not a part of a sweep's results".into()));
    }
    let mut out = Vec::new();
    for row in r.get_row_iter(None).map_err(|x| e(pq(x)))? {
        let row = row.map_err(|x| e(pq(x)))?;
        let fields: Vec<&Field> = row.get_column_iter().map(|(_, f)| f).collect();
        let double = |f: &Field| match f {
            Field::Double(x) => Some(*x),
            _ => None,
        };
        let text = |f: &Field| match f {
            Field::Str(s) => s.clone(),
            _ => String::new(),
        };
        let Field::Long(run) = fields[0] else {
            return Err(e("run is not an integer".into()));
        };
        let Field::Long(warnings) = fields[n - 3] else {
            return Err(e("warnings is not an integer".into()));
        };
        // the parameters are the leading doubles that are never null: count them from the
        // metadata of the columns (REQUIRED)
        let np = (r.metadata().file_metadata().schema_descr().columns()[1..n - 3].iter())
            .take_while(|c| c.self_type().get_basic_info().repetition() == Repetition::REQUIRED)
            .count();
        let params: Vec<f64> = fields[1..1 + np].iter().filter_map(|f| double(f)).collect();
        let metrics: Vec<f64> = fields[1 + np..n - 3]
            .iter()
            .filter_map(|f| double(f))
            .collect();
        out.push(Row {
            run: *run as usize,
            params,
            metrics,
            warnings: *warnings as u64,
            warning: text(fields[n - 2]),
            error: text(fields[n - 1]),
        });
    }
    Ok(out)
}

//! A run's result: its number, the values of the swept parameters, the metrics (none when the
//! run was refused or failed), the log's warnings and the reason of a failure; and the same as
//! one line of text, exact to the bit (a number is written as Rust's shortest representation
//! that reads back to the same `f64`), which is how a Dask worker hands its rows back.

/// One run's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub run: usize,
    /// The swept parameters' values, in the order of [`super::Plan::swept`].
    pub params: Vec<f64>,
    /// The metrics, in the order of [`super::Plan::metrics`]; empty when `error` is set.
    pub metrics: Vec<f64>,
    /// Warnings the model logged during the run.
    pub warnings: u64,
    /// The first of them.
    pub warning: String,
    /// Why the run has no metrics (its parameters refused, a step refused); empty if it ran.
    pub error: String,
}

impl Row {
    /// The row as one line (no newline): fields separated by tabs, text escaped.
    pub fn to_line(&self) -> String {
        let mut out = format!(
            "{}\t{}\t{}",
            self.run,
            self.params.len(),
            self.metrics.len()
        );
        for x in self.params.iter().chain(&self.metrics) {
            out.push('\t');
            out.push_str(&format!("{x:?}"));
        }
        out.push_str(&format!(
            "\t{}\t{}\t{}",
            self.warnings,
            escape(&self.warning),
            escape(&self.error)
        ));
        out
    }

    /// Reads a line of [`Row::to_line`]; `None` if it is not one.
    pub fn from_line(line: &str) -> Option<Row> {
        let f: Vec<&str> = line.trim_end_matches(['\r', '\n']).split('\t').collect();
        let run = f.first()?.parse().ok()?;
        let np: usize = f.get(1)?.parse().ok()?;
        let nm: usize = f.get(2)?.parse().ok()?;
        if f.len() != 3 + np + nm + 3 {
            return None;
        }
        let num = |s: &str| s.parse::<f64>().ok();
        let params = f[3..3 + np]
            .iter()
            .map(|s| num(s))
            .collect::<Option<Vec<_>>>()?;
        let metrics = (f[3 + np..3 + np + nm].iter())
            .map(|s| num(s))
            .collect::<Option<Vec<_>>>()?;
        let k = 3 + np + nm;
        Some(Row {
            run,
            params,
            metrics,
            warnings: f[k].parse().ok()?,
            warning: unescape(f[k + 1])?,
            error: unescape(f[k + 2])?,
        })
    }
}

fn escape(s: &str) -> String {
    s.replace('\\', "\\\\")
        .replace('\t', "\\t")
        .replace('\n', "\\n")
        .replace('\r', "\\r")
}

fn unescape(s: &str) -> Option<String> {
    let mut out = String::with_capacity(s.len());
    let mut it = s.chars();
    while let Some(c) = it.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        out.push(match it.next()? {
            '\\' => '\\',
            't' => '\t',
            'n' => '\n',
            'r' => '\r',
            _ => return None,
        });
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_row_survives_its_line_bit_for_bit() {
        let r = Row {
            run: 41,
            params: vec![0.1 + 0.2, -1e-300, f64::MIN_POSITIVE / 4.0],
            metrics: vec![f64::NAN, f64::INFINITY, -0.0, 1.0 / 3.0],
            warnings: 3,
            warning: "lift-off\tat 12.5 deg\nback \\ again".into(),
            error: String::new(),
        };
        let back = Row::from_line(&r.to_line()).expect("reads");
        assert_eq!(back.run, 41);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.params), bits(&r.params));
        assert_eq!(bits(&back.metrics), bits(&r.metrics));
        assert_eq!(
            (back.warnings, &back.warning, &back.error),
            (3, &r.warning, &r.error)
        );
        assert!(!r.to_line().contains('\n'));
        assert_eq!(Row::from_line("1\t2\t0\t1.0"), None);
        assert_eq!(Row::from_line("not a row"), None);
    }
}

//! A saved FMU state and its serialized form (layout tag, GUID hash, times, values, the
//! model's state, input derivatives), validated when read.

use super::*;

/// A saved FMU state: everything that determines a run, and no pointers.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    pub(super) state: State,
    pub(super) time: f64,
    pub(super) start_time: f64,
    pub(super) stop_time: Option<f64>,
    pub(super) values: Vec<f64>,
    pub(super) model_state: Vec<f64>,
    /// The input derivatives set for the next step, `(vr, order, value)`.
    pub(super) input_derivatives: Vec<(u32, u32, f64)>,
    /// Model Exchange: in continuous-time mode (else event mode, or Co-Simulation).
    pub(super) continuous_time: bool,
    /// When the host last set an input ([`Values::inputs_at`]).
    pub(super) inputs_at: f64,
}

impl Snapshot {
    pub(super) fn to_bytes(&self, guid_hash: u128) -> Vec<u8> {
        let mut b = Vec::with_capacity(64 + 8 * (self.values.len() + self.model_state.len()));
        b.extend_from_slice(STATE_MAGIC);
        b.extend_from_slice(&guid_hash.to_le_bytes());
        b.extend_from_slice(&self.state.code().to_le_bytes());
        for x in [
            self.time,
            self.start_time,
            self.stop_time.unwrap_or(f64::NAN),
            self.inputs_at,
        ] {
            b.extend_from_slice(&x.to_bits().to_le_bytes());
        }
        b.push(self.stop_time.is_some() as u8);
        let ders: Vec<f64> = self
            .input_derivatives
            .iter()
            .flat_map(|&(vr, order, x)| [f64::from(vr), f64::from(order), x])
            .collect();
        for v in [&self.values, &self.model_state, &ders] {
            b.extend_from_slice(&(v.len() as u64).to_le_bytes());
            for x in v.iter() {
                b.extend_from_slice(&x.to_bits().to_le_bytes());
            }
        }
        b.push(self.continuous_time as u8);
        b
    }

    pub(super) fn from_bytes(
        bytes: &[u8],
        guid_hash: u128,
        n_values: usize,
    ) -> Result<Snapshot, String> {
        let mut r = Reader { b: bytes, at: 0 };
        if r.take(8)? != STATE_MAGIC {
            return Err("not a serialized state of a bindery-fmu FMU".into());
        }
        if u128::from_le_bytes(r.take(16)?.try_into().unwrap()) != guid_hash {
            return Err("serialized state belongs to another FMU (GUID differs)".into());
        }
        let code = u16::from_le_bytes(r.take(2)?.try_into().unwrap());
        let state = State::from_code(code).ok_or_else(|| format!("unknown state code {code}"))?;
        let time = r.f64()?;
        let start_time = r.f64()?;
        let stop = r.f64()?;
        let inputs_at = r.f64()?;
        if !inputs_at.is_finite() {
            return Err(format!("serialized input time {inputs_at} is not finite"));
        }
        let stop_defined = r.take(1)?[0] == 1;
        let values = r.vec()?;
        if values.len() != n_values {
            return Err(format!(
                "serialized state has {} values, this FMU {}",
                values.len(),
                n_values
            ));
        }
        let model_state = r.vec()?;
        let ders = r.vec()?;
        if ders.len() % 3 != 0 {
            return Err(format!(
                "serialized input derivatives: {} numbers, not triples",
                ders.len()
            ));
        }
        // (vr, order) are checked against the variables in `Instance::restore`; here only
        // that they are whole numbers in range
        let mut input_derivatives = Vec::with_capacity(ders.len() / 3);
        for d in ders.chunks(3) {
            let whole = |x: f64| x >= 0.0 && x <= f64::from(u32::MAX) && x.fract() == 0.0;
            if !(whole(d[0]) && whole(d[1])) {
                return Err(format!(
                    "serialized input derivative of vr {} order {}: not a value reference and order",
                    d[0], d[1]
                ));
            }
            input_derivatives.push((d[0] as u32, d[1] as u32, d[2]));
        }
        let continuous_time = match r.take(1)?[0] {
            0 => false,
            1 => true,
            m => {
                return Err(format!(
                    "unknown Model Exchange mode {m} in serialized state"
                ));
            }
        };
        if r.at != bytes.len() {
            return Err(format!(
                "{} trailing bytes in serialized state",
                bytes.len() - r.at
            ));
        }
        Ok(Snapshot {
            state,
            time,
            start_time,
            stop_time: stop_defined.then_some(stop),
            values,
            model_state,
            input_derivatives,
            continuous_time,
            inputs_at,
        })
    }
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.b.len())
            .ok_or("serialized state is truncated")?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_bits(u64::from_le_bytes(
            self.take(8)?.try_into().unwrap(),
        )))
    }
    fn vec(&mut self) -> Result<Vec<f64>, String> {
        let n = u64::from_le_bytes(self.take(8)?.try_into().unwrap()) as usize;
        if n > self.b.len() / 8 {
            return Err("serialized state is truncated".into());
        }
        (0..n).map(|_| self.f64()).collect()
    }
}

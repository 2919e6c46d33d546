//! The oracle's own compiled form of a plan: fixed-point integers exactly as
//! docs/semantics.md ("Numbers: exact fixed point") says. Independent of the
//! engine's `scheduler::Problem`.

use solscope_engine::{AwakeMode, EffectAt, Plan};

/// `x * 10^decimals * factor` rounded up (`up`) or down, from `x` as the
/// planner wrote it (its shortest decimal, as `Display` prints it), in exact
/// integer arithmetic. `None` when that has more digits than the oracle handles.
fn scaled(x: f64, decimals: u32, factor: i128, up: bool) -> Option<i128> {
    let text = format!("{x}");
    let (neg, body) = match text.strip_prefix('-') {
        Some(b) => (true, b),
        None => (false, text.as_str()),
    };
    let (int, frac) = body.split_once('.').unwrap_or((body, ""));
    let frac = frac.trim_end_matches('0');
    let int = int.trim_start_matches('0');
    if int.len() + frac.len() > 30 {
        return None;
    }
    let digits: i128 = format!("0{int}{frac}").parse().ok()?;
    let num = digits
        .checked_mul(factor)?
        .checked_mul(10i128.checked_pow(decimals)?)?;
    let num = if neg { -num } else { num };
    let den = 10i128.checked_pow(u32::try_from(frac.len()).ok()?)?;
    let floor = num.div_euclid(den);
    Some(if up && num.rem_euclid(den) != 0 {
        floor + 1
    } else {
        floor
    })
}

/// How the oracle turns plan figures into integers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Units {
    /// As docs/semantics.md says the scheduler does: mW, mJ, bit, each figure
    /// rounded to its safe side.
    Scheduler,
    /// Exactly, in nW, nJ and millibit (an error if a figure is finer than that):
    /// the plan's own decimals, for checking that the rounding is safe.
    Exact,
}

impl Units {
    /// (decimals, factor) per W, Wh and Mbit.
    fn parts(self) -> [(u32, i128); 3] {
        match self {
            Units::Scheduler => [(3, 1), (5, 36), (6, 1)],
            Units::Exact => [(9, 1), (11, 36), (9, 1)],
        }
    }

    fn convert(self, x: f64, kind: usize, up: bool) -> Result<i64, String> {
        let (d, f) = self.parts()[kind];
        let v = scaled(x, d, f, up).ok_or_else(|| format!("oracle: {x} has too many digits"))?;
        if self == Units::Exact && scaled(x, d, f, !up) != Some(v) {
            return Err(format!("oracle: {x} is finer than the exact units"));
        }
        i64::try_from(v).map_err(|_| format!("oracle: {x} out of range"))
    }

    /// A power (W): a load `up`, a supply or upper limit down.
    pub fn power(self, x: f64, up: bool) -> Result<i64, String> {
        self.convert(x, 0, up)
    }

    /// An energy (Wh).
    pub fn energy(self, x: f64, up: bool) -> Result<i64, String> {
        self.convert(x, 1, up)
    }

    /// A data volume (Mbit) or rate (Mbit/s).
    pub fn data(self, x: f64, up: bool) -> Result<i64, String> {
        self.convert(x, 2, up)
    }
}

/// A power figure in mW, as the scheduler reads a load (rounded up).
pub fn mw(x: f64) -> i64 {
    Units::Scheduler.power(x, true).unwrap_or(i64::MAX)
}

/// A start window, with the defaults filled in.
#[derive(Clone, Copy, Debug)]
pub struct Win {
    pub start: i64,
    pub end: i64,
    pub preferred: i64,
    pub cutoff: Option<i64>,
}

#[derive(Clone, Debug)]
pub struct Dep {
    pub target: usize,
    pub meets: bool,
    pub min_delay: i64,
    pub max_delay: Option<i64>,
}

#[derive(Clone, Debug)]
pub struct Act {
    pub id: String,
    pub mandatory: bool,
    pub dmin: i64,
    pub dmax: i64,
    pub windows: Vec<Win>,
    pub resources: Vec<String>,
    pub engines: i64,
    pub energy_mw: i64,
    pub peak_mw: i64,
    pub data_bps: i64,
    pub awake: AwakeMode,
    pub zones: Vec<usize>,
    pub after: Vec<Dep>,
    /// (state index, value)
    pub requires: Vec<(usize, String)>,
    /// (state index, value, at start?)
    pub effects: Vec<(usize, String, bool)>,
    pub uhf: Option<Vec<String>>,
    pub comm: Option<String>,
    pub group: Option<String>,
}

#[derive(Clone, Debug)]
pub struct Zone {
    pub name: String,
    /// (from, duration)
    pub table: Vec<(i64, i64)>,
    pub preheat_mw: i64,
    pub maint_mw: i64,
    /// (from, to), local time of day; `None`: always operable.
    pub operable: Option<Vec<(i64, i64)>>,
}

#[derive(Clone, Debug)]
pub struct Prob {
    pub hs: i64,
    pub he: i64,
    pub sol_len: i64,
    pub offset: i64,
    pub cap_mj: i64,
    pub init_mj: i64,
    pub min_mj: i64,
    pub rtg_mw: i64,
    pub asleep_mw: i64,
    pub awake_mw: i64,
    pub max_peak_mw: Option<i64>,
    pub wake: i64,
    pub shut: i64,
    pub min_awake: i64,
    pub min_sleep: i64,
    pub engines: Option<i64>,
    pub data_cap: Option<i64>,
    pub data_init: i64,
    pub ho_time: Option<i64>,
    pub ho_min_mj: Option<i64>,
    pub ho_max_bits: Option<i64>,
    /// (name, initial value)
    pub states: Vec<(String, String)>,
    pub zones: Vec<Zone>,
    pub acts: Vec<Act>,
    /// Step order: activity indices sorted by (priority, file index).
    pub order: Vec<usize>,
}

impl Prob {
    pub fn compile(plan: &Plan) -> Result<Prob, String> {
        Self::compile_with(plan, Units::Scheduler)
    }

    /// Compiled with the given units (`Units::Exact`: every figure exactly; the
    /// names' `mw`/`mj`/`bits` then mean nW, nJ and millibit).
    pub fn compile_with(plan: &Plan, units: Units) -> Result<Prob, String> {
        const UP: bool = true;
        const DOWN: bool = false;
        let hs = plan.horizon.start;
        let he = plan.horizon.end;
        if he <= hs {
            return Err("oracle: empty horizon".into());
        }
        let states: Vec<(String, String)> = plan
            .states
            .iter()
            .map(|(k, v)| (k.clone(), v.initial.clone()))
            .collect();
        let state_idx = |name: &str| -> Result<usize, String> {
            states
                .iter()
                .position(|(n, _)| n == name)
                .ok_or_else(|| format!("oracle: unknown state {name}"))
        };
        let zones: Vec<Zone> = plan
            .thermal_zones
            .iter()
            .map(|(name, z)| {
                Ok(Zone {
                    name: name.clone(),
                    table: z.preheat.iter().map(|e| (e.from, e.duration)).collect(),
                    preheat_mw: units.power(z.preheat_power, UP)?,
                    maint_mw: units.power(z.maintenance_power, UP)?,
                    operable: z
                        .operable
                        .as_ref()
                        .map(|v| v.iter().map(|p| (p.from, p.to)).collect()),
                })
            })
            .collect::<Result<_, String>>()?;
        let zone_idx = |name: &str| -> Result<usize, String> {
            zones
                .iter()
                .position(|z| z.name == name)
                .ok_or_else(|| format!("oracle: unknown zone {name}"))
        };
        let act_idx = |id: &str| -> Result<usize, String> {
            plan.activities
                .iter()
                .position(|a| a.id == id)
                .ok_or_else(|| format!("oracle: unknown activity {id}"))
        };
        let mut acts = Vec::new();
        for a in &plan.activities {
            let windows = match &a.windows {
                None => vec![Win {
                    start: hs,
                    end: he,
                    preferred: hs,
                    cutoff: None,
                }],
                Some(ws) => ws
                    .iter()
                    .map(|w| Win {
                        start: w.start,
                        end: w.end,
                        preferred: w.preferred.unwrap_or(w.start),
                        cutoff: w.cutoff,
                    })
                    .collect(),
            };
            let mut after = Vec::new();
            for d in &a.after {
                after.push(Dep {
                    target: act_idx(&d.activity)?,
                    meets: d.meets,
                    min_delay: d.min_delay.unwrap_or(0),
                    max_delay: d.max_delay,
                });
            }
            let mut requires = Vec::new();
            for r in &a.requires {
                requires.push((state_idx(&r.state)?, r.value.clone()));
            }
            let mut effects = Vec::new();
            for e in &a.effects {
                effects.push((
                    state_idx(&e.state)?,
                    e.value.clone(),
                    e.at == EffectAt::Start,
                ));
            }
            let mut zs = Vec::new();
            for z in &a.thermal_zones {
                zs.push(zone_idx(z)?);
            }
            acts.push(Act {
                id: a.id.clone(),
                mandatory: a.mandatory,
                dmin: a.duration.min(),
                dmax: a.duration.max(),
                windows,
                resources: a.resources.clone(),
                engines: i64::from(a.sequence_engines),
                energy_mw: units.power(a.energy_rate, UP)?,
                peak_mw: units.power(a.peak_power, UP)?,
                data_bps: units.data(a.data_rate, UP)?,
                awake: a.awake,
                zones: zs,
                after,
                requires,
                effects,
                uhf: a.uhf_interactions.clone(),
                comm: a.comm_kind.clone(),
                group: a.group.clone(),
            });
        }
        let mut order: Vec<usize> = (0..acts.len()).collect();
        order.sort_by_key(|&i| (plan.activities[i].priority, i));
        let ho = plan.handover.as_ref();
        Ok(Prob {
            hs,
            he,
            sol_len: plan.local_time.sol_length,
            offset: plan.local_time.offset,
            cap_mj: units.energy(plan.battery.capacity, DOWN)?,
            init_mj: units.energy(plan.battery.initial, DOWN)?,
            min_mj: units.energy(plan.battery.min_soc, UP)?,
            rtg_mw: units.power(plan.power.rtg, DOWN)?,
            asleep_mw: units.power(plan.power.asleep, UP)?,
            awake_mw: units.power(plan.power.awake, UP)?,
            max_peak_mw: plan
                .power
                .max_peak
                .map(|x| units.power(x, DOWN))
                .transpose()?,
            wake: plan.sleep.wakeup_duration,
            shut: plan.sleep.shutdown_duration,
            min_awake: plan.sleep.min_awake,
            min_sleep: plan.sleep.min_sleep,
            engines: plan.sequence_engines.map(i64::from),
            data_cap: plan
                .data
                .capacity
                .map(|x| units.data(x, DOWN))
                .transpose()?,
            data_init: units.data(plan.data.initial, UP)?,
            ho_time: ho.map(|h| h.time),
            ho_min_mj: ho
                .and_then(|h| h.min_soc)
                .map(|x| units.energy(x, UP))
                .transpose()?,
            ho_max_bits: ho
                .and_then(|h| h.max_data_volume)
                .map(|x| units.data(x, DOWN))
                .transpose()?,
            states,
            zones,
            acts,
            order,
        })
    }

    /// Local time of day of plan time `t`.
    pub fn tod(&self, t: i64) -> i64 {
        (self.offset + t).rem_euclid(self.sol_len.max(1))
    }

    /// Preheat duration of zone `z` for an activity starting at `s`.
    pub fn preheat_duration(&self, z: usize, s: i64) -> i64 {
        let tod = self.tod(s);
        let mut best: Option<(i64, i64)> = None;
        for &(from, dur) in &self.zones[z].table {
            if from <= tod && best.is_none_or(|(bf, _)| from > bf) {
                best = Some((from, dur));
            }
        }
        best.map_or(0, |(_, d)| d)
    }

    /// Whether a preheat of zone `z` may start at plan time `t`.
    pub fn operable(&self, z: usize, t: i64) -> bool {
        let tod = self.tod(t);
        match &self.zones[z].operable {
            None => true,
            Some(periods) => periods.iter().any(|&(from, to)| {
                if from <= to {
                    from <= tod && tod <= to
                } else {
                    tod >= from || tod <= to
                }
            }),
        }
    }

    pub fn horizon_len(&self) -> usize {
        (self.he - self.hs) as usize
    }
}

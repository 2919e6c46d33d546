//! The oracle's scheduling state and the brute-force feasibility test of one
//! candidate `(s, d)`, written directly from docs/semantics.md.
//!
//! Two evaluations of the resource checks exist:
//! - `naive`: rebuilds every per-second array with the candidate placed and scans
//!   the whole horizon (the reference);
//! - `fast`: re-simulates only the seconds the candidate changes and summarises
//!   the untouched prefix/suffix exactly (prefix minima, and for the capped state
//!   of charge the closed form `min(x + A[u], B[u])` of the minimum of the capped
//!   trajectory started at `x` at second `u`).
//!
//! The search uses `fast`; the chosen placement is always re-checked with `naive`,
//! and in paranoid mode every candidate is evaluated both ways and compared.

use std::fmt;

use solscope_engine::AwakeMode;

use super::problem::{Prob, Win};

pub const INF: i64 = i64::MAX / 4;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placed {
    pub act: usize,
    pub step: usize,
    pub s: i64,
    pub e: i64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AwakeP {
    pub s: i64,
    pub e: i64,
    pub step: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum HeatKind {
    Preheat,
    Maintenance,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Demand {
    pub zone: usize,
    pub kind: HeatKind,
    pub act: usize,
    pub s: i64,
    pub e: i64,
    pub mw: i64,
    pub step: usize,
}

/// A placed state effect.
#[derive(Clone, Debug)]
pub struct EffectRec {
    pub state: usize,
    pub time: i64,
    pub step: usize,
    pub act: usize,
    pub value: String,
}

/// Why a candidate is infeasible: a phase-1 category or a phase-2 reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reason {
    Execution,
    Dependency,
    UnitResource(String),
    SequenceEngines(i64),
    StateRequirement(String),
    StateEffect(String),
    DataVolume(String),
    Uhf(String),
    ForcedSleep,
    MinSleep,
    MinAwake,
    PreheatOutsidePlan(String),
    PreheatOperability(String),
    MaxPeakPower(i64, i64),
    MinSoc(i64, i64),
    HandoverSoc(i64),
}

impl Reason {
    pub fn kind(&self) -> &'static str {
        match self {
            Reason::Execution => "execution",
            Reason::Dependency => "dependency",
            Reason::UnitResource(_) => "unit_resource",
            Reason::SequenceEngines(_) => "sequence_engines",
            Reason::StateRequirement(_) => "state_requirement",
            Reason::StateEffect(_) => "state_effect",
            Reason::DataVolume(_) => "data_volume",
            Reason::Uhf(_) => "uhf",
            Reason::ForcedSleep => "forced_sleep",
            Reason::MinSleep => "min_sleep",
            Reason::MinAwake => "min_awake",
            Reason::PreheatOutsidePlan(_) => "preheat_outside_plan",
            Reason::PreheatOperability(_) => "preheat_operability",
            Reason::MaxPeakPower(..) => "max_peak_power",
            Reason::MinSoc(..) => "min_soc",
            Reason::HandoverSoc(_) => "handover_soc",
        }
    }
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::UnitResource(x)
            | Reason::StateRequirement(x)
            | Reason::StateEffect(x)
            | Reason::DataVolume(x)
            | Reason::Uhf(x)
            | Reason::PreheatOutsidePlan(x)
            | Reason::PreheatOperability(x) => write!(f, "{} ({x})", self.kind()),
            Reason::SequenceEngines(t) => write!(f, "sequence_engines (exceeded at t={t})"),
            Reason::MaxPeakPower(t, p) => write!(f, "max_peak_power ({p} mW at t={t})"),
            Reason::MinSoc(t, e) => write!(f, "min_soc ({e} mJ at t={t})"),
            Reason::HandoverSoc(e) => write!(f, "handover_soc ({e} mJ at handover)"),
            _ => f.write_str(self.kind()),
        }
    }
}

/// What placing a candidate adds to the state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Change {
    /// The new awake period `Q2` and the indices (into `World::awake`) of the
    /// periods it replaces; `None` when no awake period changes.
    pub awake: Option<((i64, i64), Vec<usize>)>,
    /// New heater demands (step filled in by `apply`).
    pub demands: Vec<Demand>,
}

/// Per-second arrays of a state; index `i` is second `hs + i`.
#[derive(Clone, Debug)]
pub struct Sim {
    pub awake_at: Vec<bool>,
    pub engines: Vec<i64>,
    pub zone_draw: Vec<Vec<i64>>,
    /// Net state-of-charge rate (mW = mJ/s).
    pub rate: Vec<i64>,
    /// Total peak power (mW).
    pub peak: Vec<i64>,
    /// Data rate (bit/s).
    pub drate: Vec<i64>,
    /// State of charge at seconds `hs..=he` (mJ).
    pub soc: Vec<i64>,
    /// Data volume at seconds `hs..=he` (bit).
    pub dvol: Vec<i64>,
}

impl Sim {
    pub fn build(p: &Prob, placed: &[Placed], awake: &[AwakeP], demands: &[Demand]) -> Sim {
        let h = p.horizon_len();
        let idx = |t: i64| (t - p.hs) as usize;
        let mut awake_at = vec![false; h];
        for a in awake {
            awake_at[idx(a.s)..idx(a.e)].fill(true);
        }
        let mut engines = vec![0i64; h];
        let mut energy = vec![0i64; h];
        let mut apeak = vec![0i64; h];
        let mut drate = vec![0i64; h];
        for pl in placed {
            let a = &p.acts[pl.act];
            for i in idx(pl.s)..idx(pl.e) {
                engines[i] += a.engines;
                energy[i] += a.energy_mw;
                apeak[i] += a.peak_mw;
                drate[i] += a.data_bps;
            }
        }
        let mut zone_draw = vec![vec![0i64; h]; p.zones.len()];
        for d in demands {
            for x in &mut zone_draw[d.zone][idx(d.s)..idx(d.e)] {
                *x = (*x).max(d.mw);
            }
        }
        let mut rate = vec![0i64; h];
        let mut peak = vec![0i64; h];
        for i in 0..h {
            let base = if awake_at[i] { p.awake_mw } else { p.asleep_mw };
            let heat: i64 = zone_draw.iter().map(|z| z[i]).sum();
            rate[i] = p.rtg_mw - base - energy[i] - heat;
            peak[i] = base + apeak[i] + heat;
        }
        let mut soc = vec![0i64; h + 1];
        soc[0] = p.init_mj;
        let mut dvol = vec![0i64; h + 1];
        dvol[0] = p.data_init;
        for i in 0..h {
            soc[i + 1] = (soc[i] + rate[i]).min(p.cap_mj);
            dvol[i + 1] = (dvol[i] + drate[i]).max(0);
        }
        Sim {
            awake_at,
            engines,
            zone_draw,
            rate,
            peak,
            drate,
            soc,
            dvol,
        }
    }
}

/// Minimum over `[u, H]` of the capped trajectory `x(t+1) = min(cap, x(t) + r(t))`
/// started at `x` at `u`: `min(x + a[u], b[u])`.
#[derive(Clone, Debug)]
pub struct SufMin {
    a: Vec<i64>,
    b: Vec<i64>,
}

impl SufMin {
    fn build(rate: &[i64], cap: i64) -> SufMin {
        let h = rate.len();
        let mut a = vec![0i64; h + 1];
        let mut b = vec![INF; h + 1];
        for u in (0..h).rev() {
            a[u] = (rate[u] + a[u + 1]).min(0);
            b[u] = (cap + a[u + 1]).min(b[u + 1]);
        }
        SufMin { a, b }
    }
    fn eval(&self, u: usize, x: i64) -> i64 {
        (x + self.a[u]).min(self.b[u])
    }
}

/// Value at `target` of the capped trajectory started at `x` at `u <= target`:
/// `min(x + r[u], k[u])`.
#[derive(Clone, Debug)]
pub struct AtFn {
    r: Vec<i64>,
    k: Vec<i64>,
}

impl AtFn {
    fn build(rate: &[i64], cap: i64, target: usize) -> AtFn {
        let mut r = vec![0i64; target + 1];
        let mut k = vec![INF; target + 1];
        for u in (0..target).rev() {
            r[u] = rate[u] + r[u + 1];
            k[u] = (cap + r[u + 1]).min(k[u + 1]);
        }
        AtFn { r, k }
    }
    fn eval(&self, u: usize, x: i64) -> i64 {
        (x + self.r[u]).min(self.k[u])
    }
}

/// Summaries of a `Sim` for the fast evaluation.
#[derive(Clone, Debug)]
pub struct Fast {
    soc_premin: Vec<i64>,
    soc_suf: SufMin,
    soc_ho: Option<(usize, AtFn)>,
    /// max of dvol over [0, i]
    dvol_premax: Vec<i64>,
    /// on F = -dvol (capped at 0 from above, rate -drate)
    dneg_suf: SufMin,
    /// max of peak over [0, i)
    peak_premax: Vec<i64>,
    /// max of peak over [i, H)
    peak_sufmax: Vec<i64>,
}

impl Fast {
    fn build(p: &Prob, sim: &Sim) -> Fast {
        let h = p.horizon_len();
        let mut soc_premin = sim.soc.clone();
        let mut dvol_premax = sim.dvol.clone();
        for i in 1..=h {
            soc_premin[i] = soc_premin[i].min(soc_premin[i - 1]);
            dvol_premax[i] = dvol_premax[i].max(dvol_premax[i - 1]);
        }
        let mut peak_premax = vec![-INF; h + 1];
        let mut peak_sufmax = vec![-INF; h + 1];
        for i in 0..h {
            peak_premax[i + 1] = peak_premax[i].max(sim.peak[i]);
        }
        for i in (0..h).rev() {
            peak_sufmax[i] = peak_sufmax[i + 1].max(sim.peak[i]);
        }
        let neg: Vec<i64> = sim.drate.iter().map(|&q| -q).collect();
        Fast {
            soc_premin,
            soc_suf: SufMin::build(&sim.rate, p.cap_mj),
            soc_ho: p.ho_time.map(|t| {
                let hi = ho_index(p, t);
                (hi, AtFn::build(&sim.rate, p.cap_mj, hi))
            }),
            dvol_premax,
            dneg_suf: SufMin::build(&neg, 0),
            peak_premax,
            peak_sufmax,
        }
    }
}

/// Index of the handover second (clamped into the horizon).
pub fn ho_index(p: &Prob, t: i64) -> usize {
    (t.clamp(p.hs, p.he) - p.hs) as usize
}

fn overlaps(a: (i64, i64), b: (i64, i64)) -> bool {
    a.0 < b.1 && b.0 < a.1
}

fn overlap_len(a: (i64, i64), b: (i64, i64)) -> i64 {
    (a.1.min(b.1) - a.0.max(b.0)).max(0)
}

/// Per-step precomputation for the activity being placed.
#[derive(Clone, Debug)]
pub struct StepCtx {
    act: usize,
    /// prefix counts of seconds where this activity's engines would exceed the limit
    eng_bad: Option<Vec<u32>>,
    /// per requirement: prefix counts of seconds where the state has another value
    req_bad: Vec<Vec<u32>>,
}

/// The oracle's scheduling state.
#[derive(Clone, Debug)]
pub struct World<'p> {
    pub p: &'p Prob,
    /// An activity taken out to be placed again (free slack): dependencies on it
    /// are not checked.
    pub absent: Option<usize>,
    pub placed: Vec<Placed>,
    /// per activity: its placement, if scheduled
    pub sched: Vec<Option<(i64, i64)>>,
    pub awake: Vec<AwakeP>,
    pub demands: Vec<Demand>,
    pub effects: Vec<EffectRec>,
    /// handover data produced by placed activities (bit)
    pub produced: i64,
    pub sim: Sim,
    fast: Fast,
}

/// Which windows the execution category uses.
#[derive(Clone, Copy, Debug)]
pub enum WinSel<'a> {
    One(&'a Win),
    Any,
}

impl<'p> World<'p> {
    pub fn new(p: &'p Prob) -> World<'p> {
        let sim = Sim::build(p, &[], &[], &[]);
        let fast = Fast::build(p, &sim);
        World {
            absent: None,
            p,
            placed: Vec::new(),
            sched: vec![None; p.acts.len()],
            awake: Vec::new(),
            demands: Vec::new(),
            effects: Vec::new(),
            produced: 0,
            sim,
            fast,
        }
    }

    fn idx(&self, t: i64) -> usize {
        (t - self.p.hs) as usize
    }

    /// Handover data an activity produces over `[s, e)`.
    fn ho_produced(&self, act: usize, s: i64, e: i64) -> i64 {
        match self.p.ho_time {
            Some(h) => self.p.acts[act].data_bps.max(0) * overlap_len((s, e), (self.p.hs, h)),
            None => 0,
        }
    }

    /// The value of state `st` at second `t`, excluding the effects of `exclude`,
    /// plus `extra` effects `(time, value)` of the activity being placed (which
    /// comes after every placed step).
    pub fn state_value<'a>(
        &'a self,
        st: usize,
        t: i64,
        exclude: Option<usize>,
        extra: &'a [(i64, &'a str)],
    ) -> &'a str {
        let mut best: Option<(i64, usize, &str)> = None;
        for e in &self.effects {
            if e.state == st && e.time <= t && Some(e.act) != exclude {
                let key = (e.time, e.step);
                if best.is_none_or(|(bt, bs, _)| key > (bt, bs)) {
                    best = Some((e.time, e.step, &e.value));
                }
            }
        }
        for &(time, v) in extra {
            if time <= t && best.is_none_or(|(bt, bs, _)| (time, usize::MAX) > (bt, bs)) {
                best = Some((time, usize::MAX, v));
            }
        }
        best.map_or(self.p.states[st].1.as_str(), |(_, _, v)| v)
    }

    pub fn step_ctx(&self, ai: usize) -> StepCtx {
        let p = self.p;
        let a = &p.acts[ai];
        let h = p.horizon_len();
        let eng_bad = match p.engines {
            Some(limit) if a.engines > 0 => {
                let mut pre = vec![0u32; h + 1];
                for i in 0..h {
                    pre[i + 1] = pre[i] + u32::from(self.sim.engines[i] + a.engines > limit);
                }
                Some(pre)
            }
            _ => None,
        };
        let mut req_bad = Vec::new();
        for (st, v) in &a.requires {
            let mut pre = vec![0u32; h + 1];
            for i in 0..h {
                let t = p.hs + i as i64;
                let bad = self.state_value(*st, t, None, &[]) != v.as_str();
                pre[i + 1] = pre[i] + u32::from(bad);
            }
            req_bad.push(pre);
        }
        StepCtx {
            act: ai,
            eng_bad,
            req_bad,
        }
    }

    /// Phase 1: the constraint categories. `naive_data` selects the full-rebuild
    /// data volume check.
    pub fn phase1(
        &self,
        ctx: &StepCtx,
        s: i64,
        d: i64,
        win: WinSel<'_>,
        naive_data: bool,
    ) -> Result<(), Reason> {
        let p = self.p;
        let ai = ctx.act;
        let a = &p.acts[ai];
        let e = s + d;
        // execution
        if s < p.hs || e > p.he {
            return Err(Reason::Execution);
        }
        if a.awake == AwakeMode::Required && (s - p.wake < p.hs || e + p.shut > p.he) {
            return Err(Reason::Execution);
        }
        let in_win = |w: &Win| w.start <= s && s <= w.end && w.cutoff.is_none_or(|c| e <= c);
        let ok = match win {
            WinSel::One(w) => in_win(w),
            WinSel::Any => a.windows.iter().any(in_win),
        };
        if !ok {
            return Err(Reason::Execution);
        }
        // dependency
        for dep in &a.after {
            if Some(dep.target) == self.absent {
                continue;
            }
            let Some((_, oe)) = self.sched[dep.target] else {
                return Err(Reason::Dependency);
            };
            if dep.meets {
                if s != oe {
                    return Err(Reason::Dependency);
                }
            } else if s < oe + dep.min_delay || dep.max_delay.is_some_and(|m| s > oe + m) {
                return Err(Reason::Dependency);
            }
        }
        // sequence engines (cheap, prefix counts)
        if let Some(pre) = &ctx.eng_bad {
            let (i0, i1) = (self.idx(s), self.idx(e));
            if pre[i1] != pre[i0] {
                let first = (i0..i1).find(|&i| pre[i + 1] != pre[i]).unwrap_or(i0);
                return Err(Reason::SequenceEngines(p.hs + first as i64));
            }
        }
        // state requirements (prefix counts)
        for (k, pre) in ctx.req_bad.iter().enumerate() {
            if pre[self.idx(e)] != pre[self.idx(s)] {
                let (st, v) = &a.requires[k];
                return Err(Reason::StateRequirement(format!(
                    "{} != {v} somewhere in [{s}, {e})",
                    p.states[*st].0
                )));
            }
        }
        // unit resources and uhf
        for pl in &self.placed {
            if !overlaps((s, e), (pl.s, pl.e)) {
                continue;
            }
            let o = &p.acts[pl.act];
            if let Some(r) = a.resources.iter().find(|r| o.resources.contains(r)) {
                return Err(Reason::UnitResource(format!("{r} held by {}", o.id)));
            }
            if let (Some(k), Some(list)) = (&o.comm, &a.uhf) {
                if !list.contains(k) {
                    return Err(Reason::Uhf(format!("overlaps comm {} of kind {k}", o.id)));
                }
            }
            if let (Some(k), Some(list)) = (&a.comm, &o.uhf) {
                if !list.contains(k) {
                    return Err(Reason::Uhf(format!("{} excludes kind {k}", o.id)));
                }
            }
        }
        // state effects
        if !a.effects.is_empty() {
            self.check_effects(ai, s, e)?;
        }
        // data volume
        if naive_data {
            self.data_naive(ai, s, e)
        } else {
            self.data_fast(ai, s, e)
        }
    }

    fn cand_effects(&self, ai: usize, s: i64, e: i64, st: usize) -> Vec<(i64, &str)> {
        self.p.acts[ai]
            .effects
            .iter()
            .filter(|(x, _, _)| *x == st)
            .map(|(_, v, at_start)| (if *at_start { s } else { e }, v.as_str()))
            .collect()
    }

    fn check_effects(&self, ai: usize, s: i64, e: i64) -> Result<(), Reason> {
        let p = self.p;
        for pl in &self.placed {
            let o = &p.acts[pl.act];
            for (st, v) in &o.requires {
                let extra = self.cand_effects(ai, s, e, *st);
                if extra.is_empty() {
                    continue;
                }
                // The seen value is piecewise constant, changing only at effect
                // times: check the interval's first second and every effect time.
                let mut times: Vec<i64> = vec![pl.s];
                times.extend(
                    self.effects
                        .iter()
                        .filter(|x| x.state == *st && x.act != pl.act)
                        .map(|x| x.time),
                );
                times.extend(extra.iter().map(|x| x.0));
                for t in times {
                    if t < pl.s || t >= pl.e {
                        continue;
                    }
                    let before = self.state_value(*st, t, Some(pl.act), &[]);
                    let after = self.state_value(*st, t, Some(pl.act), &extra);
                    if before != after {
                        return Err(Reason::StateEffect(format!(
                            "changes {} to {after} at {t}, required {v} by {}",
                            p.states[*st].0, o.id
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    fn data_fast(&self, ai: usize, s: i64, e: i64) -> Result<(), Reason> {
        let p = self.p;
        let a = &p.acts[ai];
        if let Some(cap) = p.data_cap {
            let (i0, i1) = (self.idx(s), self.idx(e));
            if self.fast.dvol_premax[i0] > cap {
                return Err(Reason::DataVolume("capacity exceeded before start".into()));
            }
            let mut x = self.sim.dvol[i0];
            for i in i0..i1 {
                x = (x + self.sim.drate[i] + a.data_bps).max(0);
                if x > cap {
                    return Err(Reason::DataVolume(format!(
                        "{x} bit > capacity at t={}",
                        p.hs + i as i64 + 1
                    )));
                }
            }
            if -self.fast.dneg_suf.eval(i1, -x) > cap {
                return Err(Reason::DataVolume("capacity exceeded after end".into()));
            }
        }
        self.data_handover(ai, s, e)
    }

    fn data_naive(&self, ai: usize, s: i64, e: i64) -> Result<(), Reason> {
        let p = self.p;
        if let Some(cap) = p.data_cap {
            let mut placed = self.placed.clone();
            placed.push(Placed {
                act: ai,
                step: usize::MAX,
                s,
                e,
            });
            let sim = Sim::build(p, &placed, &self.awake, &self.demands);
            if let Some(i) = sim.dvol.iter().position(|&x| x > cap) {
                return Err(Reason::DataVolume(format!(
                    "{} bit > capacity at t={}",
                    sim.dvol[i],
                    p.hs + i as i64
                )));
            }
        }
        self.data_handover(ai, s, e)
    }

    fn data_handover(&self, ai: usize, s: i64, e: i64) -> Result<(), Reason> {
        let p = self.p;
        if !p.acts[ai].mandatory {
            if let Some(max) = p.ho_max_bits {
                let total = self.produced + self.ho_produced(ai, s, e);
                if total > max {
                    return Err(Reason::DataVolume(format!(
                        "handover data {total} bit > {max}"
                    )));
                }
            }
        }
        Ok(())
    }

    /// Merges into `q` every awake period whose gap is < max(min_sleep, 1).
    fn merge(&self, mut q: (i64, i64)) -> ((i64, i64), Vec<usize>) {
        let thr = self.p.min_sleep.max(1);
        let mut merged: Vec<usize> = Vec::new();
        loop {
            let mut changed = false;
            for (i, a) in self.awake.iter().enumerate() {
                if merged.contains(&i) {
                    continue;
                }
                let gap = (a.s - q.1).max(q.0 - a.e);
                if gap < thr {
                    q = (q.0.min(a.s), q.1.max(a.e));
                    merged.push(i);
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        merged.sort_unstable();
        (q, merged)
    }

    fn forbidden_overlaps(&self, q: (i64, i64)) -> bool {
        self.placed.iter().any(|pl| {
            self.p.acts[pl.act].awake == AwakeMode::Forbidden && overlaps(q, (pl.s, pl.e))
        })
    }

    /// Phase 2, structural part: awake periods and heating.
    pub fn phase2_struct(&self, ai: usize, s: i64, d: i64) -> Result<Change, Reason> {
        let p = self.p;
        let a = &p.acts[ai];
        let e = s + d;
        let mut change = Change {
            awake: None,
            demands: Vec::new(),
        };
        match a.awake {
            AwakeMode::Any => {}
            AwakeMode::Forbidden => {
                if self.awake.iter().any(|w| overlaps((w.s, w.e), (s, e))) {
                    return Err(Reason::ForcedSleep);
                }
            }
            AwakeMode::Required => {
                let need = (s - p.wake, e + p.shut);
                if self.forbidden_overlaps(need) {
                    return Err(Reason::ForcedSleep);
                }
                let contained = self.awake.iter().any(|w| w.s <= need.0 && need.1 <= w.e);
                if !contained {
                    let (q1, m1) = self.merge(need);
                    if self.forbidden_overlaps(q1) {
                        return Err(Reason::MinSleep);
                    }
                    let (q2, m2) = if q1.1 - q1.0 < p.min_awake {
                        let mut ext = (q1.0, q1.0 + p.min_awake);
                        if ext.1 > p.he {
                            ext = (q1.1 - p.min_awake, q1.1);
                            if ext.0 < p.hs {
                                return Err(Reason::MinAwake);
                            }
                        }
                        self.merge(ext)
                    } else {
                        (q1, m1)
                    };
                    if self.forbidden_overlaps(q2) {
                        return Err(Reason::MinAwake);
                    }
                    change.awake = Some((q2, m2));
                }
            }
        }
        // heating
        let mut outside: Option<Reason> = None;
        let mut inoperable: Option<Reason> = None;
        let mut seen: Vec<usize> = Vec::new();
        for &z in &a.zones {
            if seen.contains(&z) {
                continue;
            }
            seen.push(z);
            let zone = &p.zones[z];
            change.demands.push(Demand {
                zone: z,
                kind: HeatKind::Maintenance,
                act: ai,
                s,
                e,
                mw: zone.maint_mw,
                step: 0,
            });
            let on = self
                .demands
                .iter()
                .any(|x| x.zone == z && x.s < s && s <= x.e); // covers second s - 1
            if on {
                continue;
            }
            let dur = p.preheat_duration(z, s);
            if dur <= 0 {
                continue;
            }
            let ps = s - dur;
            if ps < p.hs {
                outside.get_or_insert(Reason::PreheatOutsidePlan(format!(
                    "{} preheat would start at {ps}",
                    zone.name
                )));
            } else if !p.operable(z, ps) {
                inoperable.get_or_insert(Reason::PreheatOperability(format!(
                    "{} preheat would start at {ps} (local {})",
                    zone.name,
                    p.tod(ps)
                )));
            }
            change.demands.push(Demand {
                zone: z,
                kind: HeatKind::Preheat,
                act: ai,
                s: ps,
                e: s,
                mw: zone.preheat_mw,
                step: 0,
            });
        }
        if let Some(r) = outside.or(inoperable) {
            return Err(r);
        }
        Ok(change)
    }

    /// Phase 2 resource checks, fast form.
    fn power_fast(&self, ai: usize, s: i64, d: i64, ch: &Change) -> Result<(), Reason> {
        let p = self.p;
        let a = &p.acts[ai];
        let e = s + d;
        let mut lo = s;
        let mut hi = e;
        let q2 = ch.awake.as_ref().map(|(q, _)| *q);
        if let Some(q) = q2 {
            lo = lo.min(q.0);
            hi = hi.max(q.1);
        }
        for dm in &ch.demands {
            lo = lo.min(dm.s);
            hi = hi.max(dm.e);
        }
        let (ia, ib) = (self.idx(lo), self.idx(hi));
        let mut peak_fail: Option<Reason> = None;
        let mut soc_fail: Option<Reason> = None;
        if let Some(limit) = p.max_peak_mw {
            if self.fast.peak_premax[ia] > limit || self.fast.peak_sufmax[ib] > limit {
                let sim = &self.sim;
                let i = (0..ia)
                    .chain(ib..sim.peak.len())
                    .find(|&i| sim.peak[i] > limit)
                    .unwrap_or(0);
                peak_fail = Some(Reason::MaxPeakPower(p.hs + i as i64, sim.peak[i]));
            }
        }
        if self.fast.soc_premin[ia] < p.min_mj {
            let i = self.sim.soc.iter().position(|&x| x < p.min_mj).unwrap_or(0);
            soc_fail = Some(Reason::MinSoc(p.hs + i as i64, self.sim.soc[i]));
        }
        // handover: (min, index of the handover second, value-at-handover form)
        let ho = match (&self.fast.soc_ho, p.ho_min_mj) {
            (Some((hidx, f)), Some(min)) if !a.mandatory => Some((min, *hidx, f)),
            _ => None,
        };
        let mut ho_val: Option<i64> = None;
        if let Some((_, hidx, _)) = ho {
            if hidx <= ia {
                ho_val = Some(self.sim.soc[hidx]);
            }
        }
        let mut x = self.sim.soc[ia];
        for i in ia..ib {
            let t = p.hs + i as i64;
            let old_awake = self.sim.awake_at[i];
            let new_awake = old_awake || q2.is_some_and(|q| q.0 <= t && t < q.1);
            let dbase = if new_awake && !old_awake {
                p.awake_mw - p.asleep_mw
            } else {
                0
            };
            let running = s <= t && t < e;
            let mut dz = 0;
            for (k, dm) in ch.demands.iter().enumerate() {
                // per zone (each once): the candidate's largest demand at t
                if ch.demands[..k].iter().any(|o| o.zone == dm.zone) {
                    continue;
                }
                let cand = ch
                    .demands
                    .iter()
                    .filter(|o| o.zone == dm.zone && o.s <= t && t < o.e)
                    .map(|o| o.mw)
                    .max();
                if let Some(c) = cand {
                    let old = self.sim.zone_draw[dm.zone][i];
                    dz += old.max(c) - old;
                }
            }
            let r = self.sim.rate[i] - dbase - if running { a.energy_mw } else { 0 } - dz;
            let pk = self.sim.peak[i] + dbase + if running { a.peak_mw } else { 0 } + dz;
            if let Some(limit) = p.max_peak_mw {
                if pk > limit && peak_fail.is_none() {
                    peak_fail = Some(Reason::MaxPeakPower(t, pk));
                }
            }
            x = (x + r).min(p.cap_mj);
            if x < p.min_mj && soc_fail.is_none() {
                soc_fail = Some(Reason::MinSoc(t + 1, x));
            }
            if let Some((_, hidx, _)) = ho {
                if hidx == i + 1 {
                    ho_val = Some(x);
                }
            }
        }
        if soc_fail.is_none() {
            let m = self.fast.soc_suf.eval(ib, x);
            if m < p.min_mj {
                // somewhere at or after the changed seconds
                soc_fail = Some(Reason::MinSoc(p.hs + ib as i64, m));
            }
        }
        if let Some(r) = peak_fail.or(soc_fail) {
            return Err(r);
        }
        if let Some((min, hidx, f)) = ho {
            let v = match ho_val {
                Some(v) => v,
                None => {
                    debug_assert!(hidx > ib);
                    f.eval(ib, x)
                }
            };
            if v < min {
                return Err(Reason::HandoverSoc(v));
            }
        }
        Ok(())
    }

    /// The state's lists with a candidate applied (`step` recorded on new items).
    fn with_change(
        &self,
        ai: usize,
        step: usize,
        s: i64,
        e: i64,
        ch: &Change,
    ) -> (Vec<Placed>, Vec<AwakeP>, Vec<Demand>) {
        let mut placed = self.placed.clone();
        placed.push(Placed {
            act: ai,
            step,
            s,
            e,
        });
        let mut awake = self.awake.clone();
        if let Some((q, merged)) = &ch.awake {
            awake = awake
                .into_iter()
                .enumerate()
                .filter(|(i, _)| !merged.contains(i))
                .map(|(_, a)| a)
                .collect();
            awake.push(AwakeP {
                s: q.0,
                e: q.1,
                step,
            });
            awake.sort_by_key(|a| (a.s, a.e));
        }
        let mut demands = self.demands.clone();
        for dm in &ch.demands {
            demands.push(Demand { step, ..*dm });
        }
        (placed, awake, demands)
    }

    /// Phase 2 resource checks, naive form: rebuild and scan everything.
    fn power_naive(&self, ai: usize, s: i64, d: i64, ch: &Change) -> Result<(), Reason> {
        let p = self.p;
        let (placed, awake, demands) = self.with_change(ai, usize::MAX, s, s + d, ch);
        let sim = Sim::build(p, &placed, &awake, &demands);
        if let Some(limit) = p.max_peak_mw {
            if let Some(i) = sim.peak.iter().position(|&x| x > limit) {
                return Err(Reason::MaxPeakPower(p.hs + i as i64, sim.peak[i]));
            }
        }
        if let Some(i) = sim.soc.iter().position(|&x| x < p.min_mj) {
            return Err(Reason::MinSoc(p.hs + i as i64, sim.soc[i]));
        }
        if !p.acts[ai].mandatory {
            if let (Some(min), Some(t)) = (p.ho_min_mj, p.ho_time) {
                let v = sim.soc[ho_index(p, t)];
                if v < min {
                    return Err(Reason::HandoverSoc(v));
                }
            }
        }
        Ok(())
    }

    /// Full evaluation of a candidate. `naive`: the reference form of every
    /// resource check.
    pub fn evaluate(
        &self,
        ctx: &StepCtx,
        s: i64,
        d: i64,
        win: WinSel<'_>,
        naive: bool,
    ) -> Result<Change, Reason> {
        self.phase1(ctx, s, d, win, naive)?;
        let ch = self.phase2_struct(ctx.act, s, d)?;
        if naive {
            self.power_naive(ctx.act, s, d, &ch)?;
        } else {
            self.power_fast(ctx.act, s, d, &ch)?;
        }
        Ok(ch)
    }

    /// Places a candidate (already found feasible).
    pub fn apply(&mut self, ai: usize, step: usize, s: i64, d: i64, ch: &Change) {
        let e = s + d;
        let (placed, awake, demands) = self.with_change(ai, step, s, e, ch);
        self.placed = placed;
        self.awake = awake;
        self.demands = demands;
        self.sched[ai] = Some((s, e));
        for (st, v, at_start) in &self.p.acts[ai].effects {
            self.effects.push(EffectRec {
                state: *st,
                time: if *at_start { s } else { e },
                step,
                act: ai,
                value: v.clone(),
            });
        }
        self.produced += self.ho_produced(ai, s, e);
        self.sim = Sim::build(self.p, &self.placed, &self.awake, &self.demands);
        self.fast = Fast::build(self.p, &self.sim);
    }
}

//! What actually ran, and the executed state of charge, data volume and peak
//! power integrated from it, chunk by chunk as the execution advances (each
//! chunk `[from, to)` is final once the execution reaches `to`).

use crate::model::AwakeMode;
use crate::scheduler::Problem;

/// One thing that draws power or produces data over `[start, end)`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Draw {
    pub start: i64,
    pub end: i64,
    /// Activity load (mW), peak (mW), data rate (bit/s); zeros for heaters.
    pub energy: i64,
    pub peak: i64,
    pub data: i64,
}

/// Everything that ran: activity draws, awake intervals, heater demands.
#[derive(Clone, Debug, Default)]
pub(super) struct Record {
    pub draws: Vec<Draw>,
    /// Realized awake intervals (may overlap; their union counts).
    pub awake: Vec<(i64, i64)>,
    /// Heater demands `(zone, start, end, mW)`; a zone draws the largest at
    /// each instant.
    pub heat: Vec<(usize, i64, i64, i64)>,
}

impl Record {
    /// An activity that started at `start` and ends at `end`.
    pub fn activity(&mut self, problem: &Problem, a: usize, start: i64, end: i64) {
        let act = &problem.acts[a];
        self.draws.push(Draw {
            start,
            end,
            energy: act.energy,
            peak: act.peak,
            data: act.data,
        });
        if act.awake == AwakeMode::Required {
            self.awake.push((start, end));
        }
        for &z in &act.zones {
            self.heat
                .push((z, start, end, problem.zones[z].maintenance));
        }
    }

    /// Removes what [`Record::activity`] recorded for activity `a` over
    /// `[start, end)` (its actual end changed before the execution got there).
    pub fn forget_activity(&mut self, problem: &Problem, a: usize, start: i64, end: i64) {
        let act = &problem.acts[a];
        remove_one(&mut self.draws, |d| {
            (d.start, d.end, d.energy, d.peak, d.data)
                == (start, end, act.energy, act.peak, act.data)
        });
        if act.awake == AwakeMode::Required {
            remove_one(&mut self.awake, |w| *w == (start, end));
        }
        for &z in &act.zones {
            let m = problem.zones[z].maintenance;
            remove_one(&mut self.heat, |h| *h == (z, start, end, m));
        }
    }

    /// Whether the rover is awake over the second `t`.
    pub fn awake_at(&self, t: i64) -> bool {
        self.awake.iter().any(|&(a, b)| a <= t && t < b)
    }

    /// The start of the union of awake intervals that contains second `t`.
    pub fn awake_since(&self, t: i64) -> Option<i64> {
        if !self.awake_at(t) {
            return None;
        }
        // One pass in decreasing start: an interval passed over never joins
        // later (the start only moves down, to starts no later than its).
        let mut by_start: Vec<(i64, i64)> = Vec::with_capacity(self.awake.len());
        by_start.extend(self.awake.iter().filter(|w| w.0 < t));
        by_start.sort_unstable_by(|x, y| y.cmp(x));
        let mut start = t;
        for (a, b) in by_start {
            if a < start && start <= b {
                start = a;
            }
        }
        debug_assert_eq!(Some(start), self.awake_since_by_hops(t));
        Some(start)
    }

    /// [`Record::awake_since`] hop by hop, to the earliest start of an
    /// interval holding the current one (debug builds check the one pass).
    fn awake_since_by_hops(&self, t: i64) -> Option<i64> {
        let mut start = t;
        loop {
            let earlier = self
                .awake
                .iter()
                .filter(|&&(a, b)| a < start && start <= b)
                .map(|&(a, _)| a)
                .min();
            match earlier {
                Some(a) => start = a,
                None => return Some(start),
            }
        }
    }
}

/// Removes the first element of `v` that `pred` accepts.
fn remove_one<T>(v: &mut Vec<T>, pred: impl Fn(&T) -> bool) {
    if let Some(i) = v.iter().position(pred) {
        v.remove(i);
    }
}

/// A limit the executed profile breaks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViolationKind {
    /// The state of charge below `battery.min_soc`.
    MinSoc,
    /// The total peak power above `power.max_peak`.
    MaxPeakPower,
    /// The onboard data volume above `data.capacity`.
    DataCapacity,
    /// The state of charge at `handover.time` below `handover.min_soc`.
    HandoverSoc,
}

/// A broken limit: when it is first broken, and the worst value while broken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Violation {
    /// Which limit.
    pub kind: ViolationKind,
    /// The first second at which the executed profile breaks it.
    pub time: i64,
    /// The worst value (mJ for energy, mW for power, bit for data) and its time.
    pub worst: (i128, i64),
    /// The limit, in the same unit.
    pub limit: i128,
}

/// The executed profiles: breakpoints of the state of charge and data volume
/// (piecewise linear between them) and of the peak power (constant from each).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ExecutedProfile {
    /// `(time, mJ)`.
    pub soc: Vec<(i64, i128)>,
    /// `(time, bit)`.
    pub data: Vec<(i64, i128)>,
    /// `(time, mW)`.
    pub peak: Vec<(i64, i64)>,
    /// The realized awake periods (union), sorted.
    pub awake: Vec<(i64, i64)>,
}

/// Integrates the record forward, chunk by chunk.
#[derive(Clone, Debug)]
pub(super) struct Integrator {
    /// Integrated up to here.
    pub t: i64,
    pub soc: i128,
    pub data: i128,
    /// Data produced in `[h0, handover)` (bit).
    pub produced: i128,
    pub profile: ExecutedProfile,
    pub violations: Vec<Violation>,
    /// Lowest state of charge and its time.
    pub lowest: (i128, i64),
    /// State of charge at the handover time, once reached.
    pub at_handover: Option<i128>,
}

impl Integrator {
    pub fn new(problem: &Problem) -> Self {
        Self {
            t: problem.h0,
            soc: problem.soc0,
            data: problem.data0,
            produced: 0,
            profile: ExecutedProfile {
                soc: vec![(problem.h0, problem.soc0)],
                data: vec![(problem.h0, problem.data0)],
                ..ExecutedProfile::default()
            },
            violations: Vec::new(),
            lowest: (problem.soc0, problem.h0),
            at_handover: None,
        }
    }

    /// Integrates `[self.t, to)` from `record` (final over that span).
    pub fn advance(&mut self, problem: &Problem, record: &Record, to: i64) {
        let to = to.min(problem.h1);
        if to <= self.t {
            return;
        }
        let from = self.t;
        let mut cuts = vec![from, to];
        let inside = |x: i64| from < x && x < to;
        for d in &record.draws {
            cuts.extend([d.start, d.end].into_iter().filter(|&x| inside(x)));
        }
        for &(a, b) in &record.awake {
            cuts.extend([a, b].into_iter().filter(|&x| inside(x)));
        }
        for &(_, a, b, _) in &record.heat {
            cuts.extend([a, b].into_iter().filter(|&x| inside(x)));
        }
        if let Some(ht) = problem.handover_time.filter(|&ht| inside(ht)) {
            cuts.push(ht);
        }
        cuts.sort_unstable();
        cuts.dedup();
        let draws: Vec<&Draw> = record
            .draws
            .iter()
            .filter(|d| d.start < to && from < d.end)
            .collect();
        let heat: Vec<&(usize, i64, i64, i64)> = record
            .heat
            .iter()
            .filter(|h| h.1 < to && from < h.2)
            .collect();
        let awake: Vec<&(i64, i64)> = record
            .awake
            .iter()
            .filter(|w| w.0 < to && from < w.1)
            .collect();
        for seg in cuts.windows(2) {
            let (x, y) = (seg[0], seg[1]);
            let on = |a: i64, b: i64| a <= x && x < b;
            let base = if awake.iter().any(|w| on(w.0, w.1)) {
                problem.awake
            } else {
                problem.asleep
            };
            let (mut energy, mut peak, mut data, mut produced) = (0i64, 0i64, 0i64, 0i64);
            for d in draws.iter().filter(|d| on(d.start, d.end)) {
                energy = energy.saturating_add(d.energy);
                peak = peak.saturating_add(d.peak);
                data = data.saturating_add(d.data);
                produced = produced.saturating_add(d.data.max(0));
            }
            let mut heaters = 0i64;
            for z in 0..problem.zones.len() {
                heaters = heaters.saturating_add(
                    heat.iter()
                        .filter(|h| h.0 == z && on(h.1, h.2))
                        .map(|h| h.3)
                        .max()
                        .unwrap_or(0),
                );
            }
            if problem.handover_time == Some(x) {
                self.handover(problem, x);
            }
            self.segment(problem, x, y, problem.rtg - base - energy - heaters, data);
            let total_peak = base.saturating_add(peak).saturating_add(heaters);
            self.peak(problem, x, total_peak);
            if let Some(ht) = problem.handover_time {
                let overlap = (y.min(ht) - x).max(0);
                self.produced += i128::from(produced) * i128::from(overlap);
            }
        }
        self.t = to;
        if problem.handover_time == Some(to) {
            self.handover(problem, to);
        }
    }

    fn handover(&mut self, problem: &Problem, t: i64) {
        if self.at_handover.is_some() {
            return;
        }
        self.at_handover = Some(self.soc);
        if let Some(min) = problem.handover_soc.filter(|&m| self.soc < m) {
            self.violations.push(Violation {
                kind: ViolationKind::HandoverSoc,
                time: t,
                worst: (self.soc, t),
                limit: min,
            });
        }
    }

    /// `[x, y)` at net charge rate `net` (mW) and data rate `rate` (bit/s).
    fn segment(&mut self, problem: &Problem, x: i64, y: i64, net: i64, rate: i64) {
        let len = i128::from(y - x);
        let net = i128::from(net);
        let before = self.soc;
        if net >= 0 {
            let full = before + net * len;
            if full > problem.capacity && before < problem.capacity && net > 0 {
                // Reaches the capacity inside the segment.
                let dt = (problem.capacity - before + net - 1) / net;
                self.profile.soc.push((x + dt as i64, problem.capacity));
            }
            self.soc = full.min(problem.capacity.max(before));
        } else {
            let after = before + net * len;
            if before >= problem.min_soc && after < problem.min_soc {
                // The first second at which the charge is below the minimum.
                let dt = (before - problem.min_soc) / (-net) + 1;
                self.note(
                    ViolationKind::MinSoc,
                    x + dt as i64,
                    after,
                    y,
                    problem.min_soc,
                );
            } else if after < problem.min_soc {
                self.note(ViolationKind::MinSoc, x, after, y, problem.min_soc);
            }
            self.soc = after;
            if after < self.lowest.0 {
                self.lowest = (after, y);
            }
        }
        self.profile.soc.push((y, self.soc));
        let d0 = self.data;
        let mut d1 = d0 + i128::from(rate) * len;
        if d1 < 0 {
            // Floored at 0 from the second it would go negative.
            let dt = (d0 + i128::from(-rate) - 1) / i128::from(-rate);
            self.profile.data.push((x + dt as i64, 0));
            d1 = 0;
        }
        if let Some(cap) = problem.data_cap.filter(|&c| d1 > c) {
            let first = if d0 > cap {
                x
            } else {
                x + ((cap - d0) / i128::from(rate) + 1) as i64
            };
            self.note(ViolationKind::DataCapacity, first, d1, y, cap);
        }
        self.data = d1;
        self.profile.data.push((y, d1));
    }

    fn peak(&mut self, problem: &Problem, x: i64, total: i64) {
        if self.profile.peak.last().is_none_or(|p| p.1 != total) {
            self.profile.peak.push((x, total));
        }
        if let Some(max) = problem.max_peak.filter(|&m| total > m) {
            self.note(
                ViolationKind::MaxPeakPower,
                x,
                i128::from(total),
                x,
                i128::from(max),
            );
        }
    }

    /// Records a breach at `time` with value `value` (at `when`): the first time
    /// is kept, and the worst value.
    fn note(&mut self, kind: ViolationKind, time: i64, value: i128, when: i64, limit: i128) {
        let worse = |old: i128| match kind {
            ViolationKind::MinSoc | ViolationKind::HandoverSoc => value < old,
            ViolationKind::MaxPeakPower | ViolationKind::DataCapacity => value > old,
        };
        match self.violations.iter_mut().find(|v| v.kind == kind) {
            Some(v) => {
                if worse(v.worst.0) {
                    v.worst = (value, when);
                }
            }
            None => self.violations.push(Violation {
                kind,
                time,
                worst: (value, when),
                limit,
            }),
        }
    }
}

/// The union of intervals, sorted.
pub(super) fn union(mut xs: Vec<(i64, i64)>) -> Vec<(i64, i64)> {
    xs.sort_unstable();
    let mut out: Vec<(i64, i64)> = Vec::new();
    for (a, b) in xs {
        match out.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => out.push((a, b)),
        }
    }
    out
}

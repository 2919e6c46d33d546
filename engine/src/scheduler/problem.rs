//! The compiled plan: interned ids and fixed-point quantities (docs/semantics.md).

use std::collections::BTreeMap;
use std::sync::Arc;

use crate::error::Error;
use crate::model::{Activity, AwakeMode, Duration, EffectAt, LocalTime, Plan, Window};
use crate::units::{Fixed, Toward, to_fixed};

/// A window in compiled form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Win {
    /// Earliest start.
    pub start: i64,
    /// Latest start.
    pub end: i64,
    /// Preferred start.
    pub preferred: i64,
    /// Latest end.
    pub cutoff: Option<i64>,
}

/// A dependency in compiled form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dep {
    /// Target activity index.
    pub target: usize,
    /// Lower bound on `start - target.end`.
    pub min_delay: i64,
    /// Upper bound on `start - target.end`.
    pub max_delay: Option<i64>,
}

/// An activity in compiled form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Act {
    /// Shortest duration.
    pub dur_min: i64,
    /// Longest duration.
    pub dur_max: i64,
    /// Mandatory?
    pub mandatory: bool,
    /// Windows (the whole horizon when the plan gives none).
    pub windows: Vec<Win>,
    /// Unit resources (interned).
    pub resources: Vec<usize>,
    /// Sequence engines held.
    pub engines: i64,
    /// Energy rate (mW).
    pub energy: i64,
    /// Peak power (mW).
    pub peak: i64,
    /// Data rate (bit/s).
    pub data: i64,
    /// Awake mode.
    pub awake: AwakeMode,
    /// Zones (indices).
    pub zones: Vec<usize>,
    /// Dependencies.
    pub after: Vec<Dep>,
    /// State requirements.
    pub requires: Vec<Requirement>,
    /// State effects.
    pub effects: Vec<Effect>,
    /// Allowed comm kinds (interned); `None` = all.
    pub uhf: Option<Vec<usize>>,
    /// Comm kind (interned).
    pub comm: Option<usize>,
    /// Group (interned).
    pub group: Option<usize>,
    /// Still executing when the cycle starts: placed first, unchecked, at its
    /// first window's start (`CycleStart::held`).
    pub held: bool,
}

impl Act {
    /// Whether this activity may overlap a comm activity of kind `kind`.
    pub fn allows(&self, kind: usize) -> bool {
        self.uhf.as_ref().is_none_or(|k| k.contains(&kind))
    }
}

/// A state requirement in compiled form: the state must hold `value` over the
/// activity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Requirement {
    /// State index (in plan order of `states`).
    pub state: usize,
    /// Value index (in the state's `values`).
    pub value: usize,
}

/// A state effect in compiled form: the activity sets `state` to `value` at its
/// start or end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Effect {
    /// State index.
    pub state: usize,
    /// Value index.
    pub value: usize,
    /// At the activity's start or end.
    pub at: EffectAt,
}

/// A thermal zone in compiled form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Zone {
    /// `(from, duration)`, sorted by `from`.
    pub table: Vec<(i64, i64)>,
    /// Preheat power (mW).
    pub preheat: i64,
    /// Maintenance power (mW).
    pub maintenance: i64,
    /// Operable periods `(from, to)` in local time; `None` = always.
    pub operable: Option<Vec<(i64, i64)>>,
}

impl Zone {
    /// The longest preheat its table gives.
    pub fn longest_preheat(&self) -> i64 {
        self.table.iter().map(|row| row.1).max().unwrap_or(0)
    }
}

/// A heater on before step 1 (a cycle of an execution; `HeaterHold`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeatHold {
    /// Zone index.
    pub zone: usize,
    /// Planned end.
    pub end: i64,
    /// Power (mW).
    pub power: i64,
    /// The activity whose preheat it is.
    pub owner: Option<usize>,
}

/// The compiled plan the scheduler works on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// Horizon start.
    pub h0: i64,
    /// Horizon end.
    pub h1: i64,
    /// Local time of day (sol length and offset).
    pub clock: LocalTime,
    /// Battery capacity (mJ).
    pub capacity: i128,
    /// Initial state of charge (mJ).
    pub soc0: i128,
    /// Minimum state of charge (mJ).
    pub min_soc: i128,
    /// RTG power (mW).
    pub rtg: i64,
    /// Asleep draw (mW).
    pub asleep: i64,
    /// Awake draw (mW).
    pub awake: i64,
    /// Peak power limit (mW).
    pub max_peak: Option<i64>,
    /// Wakeup duration.
    pub wake: i64,
    /// Shutdown duration.
    pub shut: i64,
    /// Minimum awake period.
    pub min_awake: i64,
    /// Minimum sleep between awake periods.
    pub min_sleep: i64,
    /// Sequence engines available.
    pub engines: Option<i64>,
    /// Data capacity (bit).
    pub data_cap: Option<i128>,
    /// Initial data volume (bit).
    pub data0: i128,
    /// Handover time.
    pub handover_time: Option<i64>,
    /// Handover minimum state of charge (mJ).
    pub handover_soc: Option<i128>,
    /// Handover data limit (bit).
    pub handover_data: Option<i128>,
    /// Initial value of each state (interned value index).
    pub state_initial: Vec<usize>,
    /// Zones, in name order.
    pub zones: Vec<Zone>,
    /// Zone names, in the same order.
    pub zone_names: Vec<String>,
    /// Number of distinct unit resources.
    pub resource_count: usize,
    /// Activities, in file order (shared: an edited plan's problem shares
    /// the activities the edit leaves as they were, `Problem::compile_reusing`).
    pub acts: Vec<Arc<Act>>,
    /// Step order: `order[k - 1]` is the activity of step k.
    pub order: Vec<usize>,
    /// The inverse of `order`: `step_of[a]` is the step (1-based) of activity `a`.
    pub step_of: Vec<usize>,
    /// Data already produced towards the handover limit (bit).
    pub produced0: i128,
    /// The awake period the rover is in before step 1 (a cycle of an
    /// execution): `(start, planned end)`, its start possibly before `h0`.
    pub awake0: Option<(i64, i64)>,
    /// Heaters on before step 1.
    pub heaters: Vec<HeatHold>,
}

impl Problem {
    /// How many leading steps two compiled plans share: everything but the
    /// activities equal, and the same activity, compiled the same, at each of those
    /// steps. The greedy run never looks ahead, so those steps come out the same.
    pub fn common_steps(&self, other: &Problem) -> usize {
        if !self.same_plan_wide(other) {
            return 0;
        }
        self.order
            .iter()
            .zip(&other.order)
            .take_while(|&(&a, &b)| a == b && self.acts[a] == other.acts[b])
            .count()
    }

    /// Whether `other` has the same number of activities and the same plan-wide
    /// parameters (everything but the activities and their order).
    fn same_plan_wide(&self, other: &Problem) -> bool {
        self.acts.len() == other.acts.len() && self.plan_wide() == other.plan_wide()
    }

    /// [`Problem::plan_wide`] without the limits that only checks read
    /// (`min_soc`, `max_peak`, `data_cap`, the handover limits): what every
    /// timeline of a state depends on.
    pub(crate) fn without_limits(&self) -> Problem {
        Problem {
            min_soc: 0,
            max_peak: None,
            data_cap: None,
            handover_soc: None,
            handover_data: None,
            ..self.plan_wide()
        }
    }

    /// The plan-wide parameters alone: this problem without its activities and
    /// their order (cheap to copy and compare).
    pub(crate) fn plan_wide(&self) -> Problem {
        Problem {
            acts: Vec::new(),
            order: Vec::new(),
            step_of: Vec::new(),
            zones: self.zones.clone(),
            zone_names: self.zone_names.clone(),
            state_initial: self.state_initial.clone(),
            heaters: self.heaters.clone(),
            ..*self
        }
    }

    /// Whether `other` differs from this problem in activity `a`'s definition at
    /// most: same plan-wide parameters, same step order, every other activity equal.
    pub fn differs_only_in(&self, other: &Problem, a: usize) -> bool {
        self.same_plan_wide(other)
            && self.order == other.order
            && self
                .acts
                .iter()
                .zip(&other.acts)
                .enumerate()
                .all(|(j, (x, y))| j == a || x == y)
    }

    /// The span `[start, end)` a cycle holds activity `a` over while it still
    /// executes: from its first window's start (the horizon's start without
    /// one) for its longest duration.
    pub fn held_span(&self, a: usize) -> (i64, i64) {
        let act = &self.acts[a];
        let start = act.windows.first().map_or(self.h0, |w| w.start);
        (start, start + act.dur_max)
    }

    /// Preheat duration of zone `z` for an activity starting at `s`.
    pub fn preheat_duration(&self, z: usize, s: i64) -> i64 {
        let tod = self.clock.time_of_day(s);
        let table = &self.zones[z].table;
        let i = table.partition_point(|e| e.0 <= tod);
        i.checked_sub(1).map_or(0, |i| table[i].1)
    }

    /// The handover state-of-charge minimum activity `a` must keep, as
    /// `(handover time, minimum)`: the mandatory ones are exempt.
    pub fn handover_soc_of(&self, a: usize) -> Option<(i64, i128)> {
        match (
            self.acts[a].mandatory,
            self.handover_time,
            self.handover_soc,
        ) {
            (false, Some(t), Some(min)) => Some((t, min)),
            _ => None,
        }
    }

    /// `min_soc - handover min` when the handover limit applies to activity `a`.
    pub(crate) fn handover_gap(&self, a: usize) -> Option<i128> {
        self.handover_soc_of(a).map(|(_, min)| self.min_soc - min)
    }

    /// Whether activity `a` starting at `s` finds its own preheat of zone `z`
    /// already running (a cycle of an execution).
    pub fn preheat_running(&self, a: usize, z: usize, s: i64) -> bool {
        self.heaters
            .iter()
            .any(|h| h.owner == Some(a) && h.zone == z && h.end == s)
    }

    /// Whether a preheat of zone `z` may start at plan time `t`.
    pub fn operable(&self, z: usize, t: i64) -> bool {
        let tod = self.clock.time_of_day(t);
        self.zones[z].operable.as_ref().is_none_or(|periods| {
            periods.iter().any(|&(from, to)| {
                if from <= to {
                    from <= tod && tod <= to
                } else {
                    tod >= from || tod <= to
                }
            })
        })
    }

    /// Compiles a validated plan.
    pub fn compile(plan: &Plan) -> Result<Problem, Error> {
        Self::compile_with(plan, None)
    }

    /// [`Problem::compile`] for a plan that differs from the one `base` was
    /// compiled from only in activity `edited` (`None`: in none of them; the
    /// horizon, states, thermal zones, activity ids and cycle the same): every
    /// other activity's compiled form is taken from `base` (shared, not
    /// copied) where the names it interns get the same indices, as they do
    /// unless the edit changes which activity names a resource, a comm kind
    /// or a group first. The suggestion verifier compiles thousands of edits
    /// of one plan. Debug builds compare the result with a full compile.
    pub(crate) fn compile_reusing(
        plan: &Plan,
        base: &Problem,
        edited: Option<usize>,
    ) -> Result<Problem, Error> {
        let out = Self::compile_with(plan, Some((base, edited)));
        debug_assert_eq!(
            out.as_ref().ok(),
            Self::compile(plan).as_ref().ok(),
            "compiling with the base's activities differs"
        );
        out
    }

    /// This problem, compiled from `plan`, with activity `i` replaced by
    /// `new` (an edit of it that keeps its id), compiling `new` alone: what
    /// [`Problem::compile`] gives for the plan so edited (debug builds
    /// compare). `None` when the edit changes the names first interned at
    /// `i` (a resource, UHF kind, communication kind or group that no earlier
    /// activity names), which can move other activities' indices: compile the
    /// edited plan then. The suggestion verifier compiles thousands of edits
    /// of one activity each.
    pub(crate) fn with_activity(
        &self,
        plan: &Plan,
        i: usize,
        new: &Activity,
    ) -> Option<Result<Problem, Error>> {
        let old = plan.activities.get(i)?;
        let base = self.acts.get(i)?;
        if new.id != old.id {
            return None;
        }
        let names = if new.resources == old.resources
            && new.uhf_interactions == old.uhf_interactions
            && new.comm_kind == old.comm_kind
            && new.group == old.group
        {
            Names {
                resources: base.resources.clone(),
                uhf: base.uhf.clone(),
                comm: base.comm,
                group: base.group,
            }
        } else {
            self.names_at(plan, i, old, new)?
        };
        // Ids are unique in a valid plan.
        let ids = |id: &str| plan.activities.iter().position(|a| a.id == id);
        let act = match compile_act(plan, &self.zone_names, i, new, names, &ids) {
            Ok(act) => act,
            Err(e) => return Some(Err(e)),
        };
        let mut out = self.clone();
        out.acts[i] = Arc::new(act);
        if new.priority != old.priority {
            // `i` moves in the step order, sorted by (not held, priority,
            // index); the others keep theirs.
            let key = |j: usize| {
                let p = if j == i {
                    new.priority
                } else {
                    plan.activities[j].priority
                };
                (!out.acts[j].held, p, j)
            };
            out.order.retain(|&j| j != i);
            let at = out.order.partition_point(|&j| key(j) < key(i));
            out.order.insert(at, i);
            out.step_of = step_numbers(&out.order);
        }
        Some(Ok(out))
    }

    /// The indices `new`, in place of `old` as activity `i` of `plan`, interns
    /// its names at, when the names first interned at `i` (named by no earlier
    /// activity) are the same, in the same order, for both: every other
    /// activity then keeps its indices. `None` otherwise.
    fn names_at(&self, plan: &Plan, i: usize, old: &Activity, new: &Activity) -> Option<Names> {
        // The names interned before `i`, with their indices.
        let mut resources: BTreeMap<&str, usize> = BTreeMap::new();
        let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
        let mut groups: BTreeMap<&str, usize> = BTreeMap::new();
        for (a, c) in plan.activities[..i].iter().zip(&self.acts) {
            resources.extend(
                a.resources
                    .iter()
                    .map(String::as_str)
                    .zip(c.resources.iter().copied()),
            );
            if let (Some(names), Some(ks)) = (&a.uhf_interactions, &c.uhf) {
                kinds.extend(names.iter().map(String::as_str).zip(ks.iter().copied()));
            }
            if let (Some(name), Some(k)) = (&a.comm_kind, c.comm) {
                kinds.insert(name, k);
            }
            if let (Some(name), Some(g)) = (&a.group, c.group) {
                groups.insert(name, g);
            }
        }
        // Interns an activity's names after those: its indices, and the names
        // it interned first, in order (a fresh name's index is the number
        // of names before it in its space).
        let intern_all = |a: &Activity| {
            let mut fresh: Vec<(u8, String)> = Vec::new();
            let mut take = |map: &BTreeMap<&str, usize>, space: u8, name: &str| {
                if let Some(&k) = map.get(name) {
                    return k;
                }
                let mut mine = fresh.iter().filter(|(x, _)| *x == space);
                let rank = match mine.position(|(_, n)| *n == name) {
                    Some(rank) => rank,
                    None => {
                        let rank = fresh.iter().filter(|(x, _)| *x == space).count();
                        fresh.push((space, name.to_string()));
                        rank
                    }
                };
                map.len() + rank
            };
            let names = Names {
                resources: a.resources.iter().map(|r| take(&resources, 0, r)).collect(),
                uhf: a
                    .uhf_interactions
                    .as_ref()
                    .map(|list| list.iter().map(|k| take(&kinds, 1, k)).collect()),
                comm: a.comm_kind.as_deref().map(|k| take(&kinds, 1, k)),
                group: a.group.as_deref().map(|g| take(&groups, 2, g)),
            };
            (names, fresh)
        };
        let (_, old_fresh) = intern_all(old);
        let (names, new_fresh) = intern_all(new);
        (old_fresh == new_fresh).then_some(names)
    }

    /// This problem with the plan-wide limits of `shell` (the plan without
    /// its activities, edited in its limit sections alone): what
    /// [`Problem::compile`] gives for the plan so edited, its activities,
    /// step order and heating holds taken from this problem as they are
    /// (debug builds compare the two where the caller has the edited plan).
    pub(crate) fn with_limits(&self, shell: &Plan) -> Result<Problem, Error> {
        debug_assert!(
            shell.activities.is_empty(),
            "not a plan without its activities"
        );
        let mut out = Self::compile_with(shell, None)?;
        out.acts = self.acts.clone();
        out.order = self.order.clone();
        out.step_of = self.step_of.clone();
        out.resource_count = self.resource_count;
        out.heaters = self.heaters.clone();
        Ok(out)
    }

    fn compile_with(
        plan: &Plan,
        reuse: Option<(&Problem, Option<usize>)>,
    ) -> Result<Problem, Error> {
        let ids = plan.index_by_id();
        let mut resources: BTreeMap<&str, usize> = BTreeMap::new();
        let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
        let mut groups: BTreeMap<&str, usize> = BTreeMap::new();
        let zone_names: Vec<String> = plan.thermal_zones.keys().cloned().collect();
        let mut acts = Vec::with_capacity(plan.activities.len());
        for (i, a) in plan.activities.iter().enumerate() {
            // An activity the edit left alone, compiled in `base`: what it
            // interns gets the same indices there as here (the names are
            // interned all the same, so that later activities get theirs).
            let unedited = reuse
                .filter(|(_, edited)| *edited != Some(i))
                .and_then(|(base, _)| base.acts.get(i));
            // Names interned by first appearance, for every activity (so that
            // later ones get their indices).
            let res: Vec<usize> = a
                .resources
                .iter()
                .map(|r| intern(&mut resources, r))
                .collect();
            let uhf: Option<Vec<usize>> = a
                .uhf_interactions
                .as_ref()
                .map(|list| list.iter().map(|k| intern(&mut kinds, k)).collect());
            let comm = a.comm_kind.as_deref().map(|k| intern(&mut kinds, k));
            let group = a.group.as_deref().map(|g| intern(&mut groups, g));
            if let Some(old) = unedited {
                if res == old.resources && uhf == old.uhf && comm == old.comm && group == old.group
                {
                    acts.push(Arc::clone(old));
                    continue;
                }
                // Indices moved: compile it.
            }
            let ids_of = |id: &str| ids.get(id).copied();
            let names = Names {
                resources: res,
                uhf,
                comm,
                group,
            };
            acts.push(Arc::new(compile_act(
                plan,
                &zone_names,
                i,
                a,
                names,
                &ids_of,
            )?));
        }
        // Activities still executing come first (they are not decided again).
        let mut order: Vec<usize> = (0..plan.activities.len()).collect();
        order.sort_by_key(|&i| (!acts[i].held, plan.activities[i].priority, i));
        let zones = plan
            .thermal_zones
            .values()
            .map(|z| {
                let mut table: Vec<(i64, i64)> =
                    z.preheat.iter().map(|e| (e.from, e.duration)).collect();
                table.sort_unstable();
                Zone {
                    table,
                    preheat: to_fixed(z.preheat_power, Fixed::MilliWatt, Toward::Up),
                    maintenance: to_fixed(z.maintenance_power, Fixed::MilliWatt, Toward::Up),
                    operable: z
                        .operable
                        .as_ref()
                        .map(|ps| ps.iter().map(|p| (p.from, p.to)).collect()),
                }
            })
            .collect();
        let state_initial = plan
            .states
            .iter()
            .map(|(name, s)| value_index(plan, &format!("states.{name}.initial"), name, &s.initial))
            .collect::<Result<_, _>>()?;
        // Rounded to the safe side (docs/semantics.md, "Numbers"): what the
        // battery and the data store hold, and the limits, as the exact decimals
        // would allow at most.
        let wh = |x: f64, t: Toward| i128::from(to_fixed(x, Fixed::MilliJoule, t));
        let mbit = |x: f64, t: Toward| i128::from(to_fixed(x, Fixed::Bit, t));
        let mw = |x: f64, t: Toward| to_fixed(x, Fixed::MilliWatt, t);
        let cycle = plan.cycle.clone().unwrap_or_default();
        let mut heaters = Vec::new();
        for h in &cycle.heaters {
            let zone = zone_names
                .iter()
                .position(|n| *n == h.zone)
                .ok_or_else(|| {
                    Error::invalid("cycle.heaters", format!("unknown zone \"{}\"", h.zone))
                })?;
            heaters.push(HeatHold {
                zone,
                end: h.end,
                power: h.power_mw,
                owner: h.owner.as_deref().and_then(|id| ids.get(id).copied()),
            });
        }
        Ok(Problem {
            h0: plan.horizon.start,
            h1: plan.horizon.end,
            clock: plan.local_time,
            capacity: wh(plan.battery.capacity, Toward::Down),
            soc0: if plan.cycle.is_some() {
                cycle.soc_mj
            } else {
                wh(plan.battery.initial, Toward::Down)
            },
            min_soc: wh(plan.battery.min_soc, Toward::Up),
            rtg: mw(plan.power.rtg, Toward::Down),
            asleep: mw(plan.power.asleep, Toward::Up),
            awake: mw(plan.power.awake, Toward::Up),
            max_peak: plan.power.max_peak.map(|x| mw(x, Toward::Down)),
            wake: plan.sleep.wakeup_duration,
            shut: plan.sleep.shutdown_duration,
            min_awake: plan.sleep.min_awake,
            min_sleep: plan.sleep.min_sleep,
            engines: plan.sequence_engines.map(i64::from),
            data_cap: plan.data.capacity.map(|x| mbit(x, Toward::Down)),
            data0: if plan.cycle.is_some() {
                cycle.data_bit
            } else {
                mbit(plan.data.initial, Toward::Up)
            },
            handover_time: plan.handover.map(|h| h.time),
            handover_soc: plan
                .handover
                .and_then(|h| h.min_soc)
                .map(|x| wh(x, Toward::Up)),
            handover_data: plan
                .handover
                .and_then(|h| h.max_data_volume)
                .map(|x| mbit(x, Toward::Down)),
            state_initial,
            zones,
            zone_names,
            resource_count: resources.len(),
            acts,
            step_of: step_numbers(&order),
            order,
            produced0: cycle.produced_bit,
            awake0: cycle.awake,
            heaters,
        })
    }
}

/// The indices of the names an activity interns (resources, UHF kinds, its
/// communication kind, its group), by first appearance in the plan.
struct Names {
    resources: Vec<usize>,
    uhf: Option<Vec<usize>>,
    comm: Option<usize>,
    group: Option<usize>,
}

/// An activity's windows compiled, on a horizon `[h0, h1]`: the whole
/// horizon, preferring its start, when it gives none.
pub(crate) fn compile_windows(windows: Option<&[Window]>, h0: i64, h1: i64) -> Vec<Win> {
    match windows {
        Some(ws) => ws
            .iter()
            .map(|w| Win {
                start: w.start,
                end: w.end,
                preferred: w.preferred_start(),
                cutoff: w.cutoff,
            })
            .collect(),
        None => vec![Win {
            start: h0,
            end: h1,
            preferred: h0,
            cutoff: None,
        }],
    }
}

/// Activity `i` of `plan` (`a`, which may be an edit of it) compiled, with the
/// indices of its interned names and `ids`, the index of each activity id.
fn compile_act(
    plan: &Plan,
    zone_names: &[String],
    i: usize,
    a: &Activity,
    names: Names,
    ids: &dyn Fn(&str) -> Option<usize>,
) -> Result<Act, Error> {
    let horizon = plan.horizon;
    let p = format!("activities[{i}]");
    let (dur_min, dur_max) = match a.duration {
        Duration::Fixed(d) => (d, d),
        Duration::Expanding { min, max } => (min, max),
    };
    let windows = compile_windows(a.windows.as_deref(), horizon.start, horizon.end);
    let mut zones = Vec::new();
    for (k, z) in a.thermal_zones.iter().enumerate() {
        let zi = zone_names.iter().position(|n| n == z).ok_or_else(|| {
            Error::invalid(
                format!("{p}.thermal_zones[{k}]"),
                format!("unknown zone \"{z}\""),
            )
        })?;
        zones.push(zi);
    }
    let mut after = Vec::new();
    for (k, d) in a.after.iter().enumerate() {
        let target = ids(d.activity.as_str()).ok_or_else(|| {
            Error::invalid(
                format!("{p}.after[{k}].activity"),
                format!("unknown activity \"{}\"", d.activity),
            )
        })?;
        let (min_delay, max_delay) = if d.meets {
            (0, Some(0))
        } else {
            (d.min_delay.unwrap_or(0), d.max_delay)
        };
        after.push(Dep {
            target,
            min_delay,
            max_delay,
        });
    }
    let mut requires = Vec::new();
    for (k, r) in a.requires.iter().enumerate() {
        let path = format!("{p}.requires[{k}]");
        requires.push(Requirement {
            state: state_index(plan, &path, &r.state)?,
            value: value_index(plan, &path, &r.state, &r.value)?,
        });
    }
    let mut effects = Vec::new();
    for (k, e) in a.effects.iter().enumerate() {
        let path = format!("{p}.effects[{k}]");
        effects.push(Effect {
            state: state_index(plan, &path, &e.state)?,
            value: value_index(plan, &path, &e.state, &e.value)?,
            at: e.at,
        });
    }
    Ok(Act {
        dur_min,
        dur_max,
        mandatory: a.mandatory,
        windows,
        resources: names.resources,
        engines: i64::from(a.sequence_engines),
        energy: to_fixed(a.energy_rate, Fixed::MilliWatt, Toward::Up),
        peak: to_fixed(a.peak_power, Fixed::MilliWatt, Toward::Up),
        data: to_fixed(a.data_rate, Fixed::Bit, Toward::Up),
        awake: a.awake,
        zones,
        after,
        requires,
        effects,
        uhf: names.uhf,
        comm: names.comm,
        group: names.group,
        held: plan.cycle.as_ref().is_some_and(|c| c.held.contains(&a.id)),
    })
}

/// The index of state `name`, in the plan's order of states.
fn state_index(plan: &Plan, path: &str, name: &str) -> Result<usize, Error> {
    plan.states
        .keys()
        .position(|s| s == name)
        .ok_or_else(|| Error::invalid(path, format!("unknown state \"{name}\"")))
}

/// The index of `value` among the values of state `state`.
pub(crate) fn value_index(
    plan: &Plan,
    path: &str,
    state: &str,
    value: &str,
) -> Result<usize, Error> {
    plan.states
        .get(state)
        .and_then(|s| s.values.iter().position(|v| v == value))
        .ok_or_else(|| {
            Error::invalid(
                path,
                format!("unknown value \"{value}\" for state \"{state}\""),
            )
        })
}

/// The index of `name` in `map`, adding it as the next one when new (names are
/// interned by first appearance).
fn intern<'a>(map: &mut BTreeMap<&'a str, usize>, name: &'a str) -> usize {
    let n = map.len();
    *map.entry(name).or_insert(n)
}

/// The step (1-based) of each activity, from the step order.
pub(crate) fn step_numbers(order: &[usize]) -> Vec<usize> {
    let mut step_of = vec![0; order.len()];
    for (k, &a) in order.iter().enumerate() {
        step_of[a] = k + 1;
    }
    step_of
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_plan;

    /// An edit of one activity.
    type Edit<'a> = Box<dyn Fn(&mut Activity) + 'a>;

    fn default_plan() -> Plan {
        load_plan(include_str!("../../../assets/default-plan.json"))
            .expect("the default plan loads")
            .plan
    }

    /// Compiling one edited activity alone gives the full compile of the
    /// edited plan, for edits that move it anywhere in the step order.
    #[test]
    fn one_activity_compiled_alone_is_the_full_compile() {
        let plan = default_plan();
        let base = Problem::compile(&plan).expect("compiles");
        let priorities: Vec<i64> = plan.activities.iter().map(|a| a.priority).collect();
        let (lo, hi) = (
            priorities.iter().min().copied().unwrap_or(0),
            priorities.iter().max().copied().unwrap_or(0),
        );
        let mut moved = 0;
        for i in 0..plan.activities.len() {
            let edits: Vec<Edit<'_>> = vec![
                Box::new(|a| a.priority = lo - 1),
                Box::new(|a| a.priority = hi + 1),
                Box::new(|a| a.priority = (lo + hi) / 2),
                Box::new(|a| a.priority = priorities[(i * 7) % priorities.len()]),
                Box::new(|a| a.energy_rate += 1.5),
                Box::new(|a| a.mandatory = !a.mandatory),
                Box::new(|a| a.windows = None),
                Box::new(|a| a.after.clear()),
            ];
            for edit in &edits {
                let mut edited = plan.clone();
                edit(&mut edited.activities[i]);
                let alone = base
                    .with_activity(&plan, i, &edited.activities[i])
                    .expect("the names are the same")
                    .expect("compiles");
                let full = Problem::compile(&edited).expect("compiles");
                assert_eq!(alone, full, "activity {i}");
                moved += usize::from(alone.order != base.order);
            }
        }
        assert!(moved > plan.activities.len(), "few edits moved an activity");
    }

    /// Edits of the names an activity interns: compiled alone exactly when
    /// they keep every other activity's indices, and then as in full.
    #[test]
    fn renamed_activities_compiled_alone_or_in_full() {
        // The default plan, and one where activity 1 is the first to name
        // two resources, in a group that activity 0 named first.
        let mut two_fresh = default_plan();
        two_fresh.activities[0].group = Some("shared".into());
        two_fresh.activities[1].group = Some("shared".into());
        two_fresh.activities[1].resources = vec!["fresh_a".into(), "fresh_b".into()];
        let (mut alone, mut full) = (0, 0);
        for plan in [default_plan(), two_fresh] {
            renamed(&plan, &mut alone, &mut full);
        }
        assert!(alone > 100 && full > 10, "{alone} alone, {full} in full");
    }

    fn renamed(plan: &Plan, alone: &mut usize, full: &mut usize) {
        let base = Problem::compile(plan).expect("compiles");
        for i in 0..plan.activities.len() {
            let first_group = plan.activities.iter().find_map(|a| a.group.clone());
            let first_resource = plan
                .activities
                .iter()
                .find_map(|a| a.resources.first().cloned());
            let edits: Vec<Edit<'_>> = vec![
                Box::new(|a| a.group = None),
                Box::new(|a| a.group = first_group.clone()),
                Box::new(|a| a.resources.clear()),
                Box::new(|a| a.resources.reverse()),
                Box::new(|a| a.resources.extend(first_resource.clone())),
                Box::new(|a| a.comm_kind = None),
                Box::new(|a| a.uhf_interactions = None),
                Box::new(|a| a.resources.push("new_resource".into())),
            ];
            for edit in &edits {
                let mut edited = plan.clone();
                edit(&mut edited.activities[i]);
                let want = Problem::compile(&edited).expect("compiles");
                match base.with_activity(plan, i, &edited.activities[i]) {
                    Some(got) => {
                        assert_eq!(got.expect("compiles"), want, "activity {i}");
                        *alone += 1;
                    }
                    None => {
                        // Left to a full compile: some other activity's
                        // index moves, or `i` names something new.
                        *full += 1;
                    }
                }
            }
        }
    }

    /// An edit that changes the names an activity interns is left to a full
    /// compile.
    #[test]
    fn new_names_are_compiled_in_full() {
        let plan = default_plan();
        let base = Problem::compile(&plan).expect("compiles");
        let i = plan
            .activities
            .iter()
            .position(|a| !a.resources.is_empty())
            .expect("an activity with a resource");
        let mut a = plan.activities[i].clone();
        a.resources.push("a_new_resource".into());
        assert!(base.with_activity(&plan, i, &a).is_none());
    }

    /// Compiling edited limits alone gives the full compile of the edited plan.
    #[test]
    fn limits_compiled_alone_are_the_full_compile() {
        let plan = default_plan();
        let base = Problem::compile(&plan).expect("compiles");
        let mut edited = plan.clone();
        edited.battery.min_soc *= 0.5;
        edited.power.max_peak = Some(1234.5);
        edited.sleep.min_awake += 60;
        let shell = edited.without_activities();
        assert_eq!(
            base.with_limits(&shell).expect("compiles"),
            Problem::compile(&edited).expect("compiles")
        );
    }
}

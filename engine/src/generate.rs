//! Random plans, for stress tests and benchmarks, in three profiles ([`Profile`]).
//! Deterministic per seed.
//!
//! - **standard** ([`generate_plan`]): per sol, relay and direct-to-Earth passes, a
//!   manual night sleep, arm campaigns with state changes and heating, an expanding
//!   drive with post-drive imaging, remote sensing with big/small groups, and
//!   optional environmental monitoring. The scheduler's speed was tuned on these.
//! - **realistic** ([`generate_plan_with`] and [`Profile::Realistic`]): the shapes a
//!   real multi-sol tactical plan has on top of that: activities without windows,
//!   activities with several windows (one per sol), preferred times and cutoffs,
//!   expanding activities up to four times their minimum, awake-any and night
//!   activities, start and end effects on four states, a drill with a sealing step
//!   that `meets` it, five heated zones with operable periods, UHF and X-band passes
//!   with `uhf_interactions`, and a plan offset from local midnight.
//! - **starved** ([`Profile::Starved`]): the realistic plan, over-subscribed on a
//!   battery that hovers near its minimum for days: a weak RTG, a handover
//!   minimum near the battery's, `min_sleep` without `min_awake`, wider or absent
//!   windows and more preheated activities against operable periods. Most
//!   activities fail, most of them in placement on `min_soc` or `handover_soc` at
//!   every start they try: the plans where a failing placement must be proven
//!   cheaply.
//!
//! Any profile's plan can be given uncertain durations afterwards
//! ([`add_duration_models`]): a share of its fixed-duration activities get a
//! `duration_model`, for executions, Monte Carlo campaigns and tuning.

use std::collections::BTreeMap;

use crate::model::{
    Activity, AwakeMode, Battery, Data, Dependency, Duration, DurationModel, EffectAt, Handover,
    Horizon, LocalTime, MARS_SOL, OperablePeriod, PLAN_FORMAT, Plan, Power, PreheatEntry, Sleep,
    StateDef, StateEffect, StateRequirement, ThermalZone, Window,
};

/// SplitMix64: small, fast, deterministic.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi]`.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        if hi <= lo {
            return lo;
        }
        let span = (hi - lo) as u64 + 1;
        lo + (self.next() % span) as i64
    }

    /// True with probability `p` (percent).
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[(self.next() % items.len() as u64) as usize]
    }
}

fn activity(id: String, priority: i64, duration: i64) -> Activity {
    Activity {
        id,
        name: None,
        priority,
        mandatory: true,
        duration: Duration::Fixed(duration),
        windows: None,
        resources: Vec::new(),
        sequence_engines: 1,
        energy_rate: 0.0,
        peak_power: 0.0,
        data_rate: 0.0,
        awake: AwakeMode::Required,
        thermal_zones: Vec::new(),
        after: Vec::new(),
        requires: Vec::new(),
        effects: Vec::new(),
        uhf_interactions: None,
        comm_kind: None,
        group: None,
        duration_model: None,
        value: None,
    }
}

fn window(start: i64, end: i64, preferred: Option<i64>) -> Option<Vec<Window>> {
    Some(vec![Window {
        start,
        end,
        preferred,
        cutoff: None,
    }])
}

/// A plan of about `activities` activities over `sols` sols (at least one each).
pub fn generate_plan(activities: usize, sols: usize, seed: u64) -> Plan {
    let sols = sols.max(1);
    let mut rng = Rng(seed ^ 0x0005_eed0_f501);
    let sol = MARS_SOL;
    let horizon_end = sol * sols as i64;
    let per_sol = activities.div_ceil(sols).max(1);
    let mut acts: Vec<Activity> = Vec::with_capacity(activities);
    let tod = |s: usize, hours: f64| s as i64 * sol + (hours * 3600.0) as i64;
    for s in 0..sols {
        if acts.len() >= activities {
            break;
        }
        let mut budget = per_sol.min(activities - acts.len());
        let push = |acts: &mut Vec<Activity>, a: Activity, budget: &mut usize| {
            if *budget > 0 {
                acts.push(a);
                *budget -= 1;
            }
        };
        // Comm passes: two UHF relays and a DTE pass, fixed times.
        for (k, hours) in [
            (0, 4.5 + rng.range(0, 60) as f64 / 60.0),
            (1, 16.0 + rng.range(0, 90) as f64 / 60.0),
        ] {
            let start = tod(s, hours);
            let mut a = activity(format!("s{s}_uhf{k}"), 1, 600 + rng.range(0, 4) * 150);
            a.windows = window(start, start, None);
            a.comm_kind = Some("uhf_relay".into());
            a.energy_rate = 55.0;
            a.peak_power = 90.0;
            a.data_rate = -2.0;
            push(&mut acts, a, &mut budget);
        }
        let dte = tod(s, 10.0 + rng.range(0, 120) as f64 / 60.0);
        let mut a = activity(format!("s{s}_dte"), 2, 1800);
        a.windows = window(dte, dte + 600, None);
        a.comm_kind = Some("xband".into());
        a.energy_rate = 70.0;
        a.peak_power = 170.0;
        a.data_rate = -0.5;
        push(&mut acts, a, &mut budget);
        // Night sleep.
        let night = tod(s, 20.5);
        let mut a = activity(format!("s{s}_sleep"), 3, 3 * 3600);
        a.windows = window(night, night + 1800, None);
        a.awake = AwakeMode::Forbidden;
        a.sequence_engines = 0;
        push(&mut acts, a, &mut budget);
        // Arm campaign: unstow, a few contact instruments, stow.
        let arm0 = tod(s, 8.0 + rng.range(0, 60) as f64 / 60.0);
        let mut a = activity(format!("s{s}_unstow"), 10, 600);
        a.windows = window(arm0, arm0 + 3600, None);
        a.resources = vec!["arm".into()];
        a.thermal_zones = vec!["arm".into()];
        a.energy_rate = 40.0;
        a.peak_power = 160.0;
        a.requires = vec![StateRequirement {
            state: "arm".into(),
            value: "stowed".into(),
        }];
        a.effects = vec![StateEffect {
            state: "arm".into(),
            value: "unstowed".into(),
            at: EffectAt::End,
        }];
        push(&mut acts, a, &mut budget);
        let contact = 2 + (rng.next() % 3) as usize;
        for c in 0..contact {
            let mut a = activity(
                format!("s{s}_contact{c}"),
                11 + c as i64,
                600 + rng.range(0, 12) * 150,
            );
            a.windows = window(
                arm0 + 600,
                arm0 + 5 * 3600,
                Some(arm0 + 600 + c as i64 * 1800),
            );
            a.resources = vec![
                "arm".into(),
                (*rng.pick(&["pixl", "sherloc", "watson"])).into(),
            ];
            a.thermal_zones = vec!["arm".into()];
            a.energy_rate = 35.0 + rng.range(0, 40) as f64;
            a.peak_power = 150.0 + rng.range(0, 150) as f64;
            a.data_rate = 0.05 + rng.range(0, 20) as f64 / 100.0;
            a.requires = vec![StateRequirement {
                state: "arm".into(),
                value: "unstowed".into(),
            }];
            a.after = vec![Dependency {
                activity: format!("s{s}_unstow"),
                meets: false,
                min_delay: None,
                max_delay: None,
            }];
            a.uhf_interactions = Some(vec!["xband".into()]);
            push(&mut acts, a, &mut budget);
        }
        let mut a = activity(format!("s{s}_stow"), 16, 600);
        a.windows = window(arm0 + 1800, arm0 + 7 * 3600, None);
        a.resources = vec!["arm".into()];
        a.thermal_zones = vec!["arm".into()];
        a.energy_rate = 40.0;
        a.peak_power = 160.0;
        a.effects = vec![StateEffect {
            state: "arm".into(),
            value: "stowed".into(),
            at: EffectAt::End,
        }];
        a.after = (0..contact)
            .map(|c| Dependency {
                activity: format!("s{s}_contact{c}"),
                meets: false,
                min_delay: None,
                max_delay: None,
            })
            .collect();
        push(&mut acts, a, &mut budget);
        // Drive and post-drive imaging.
        let drive0 = tod(s, 13.0);
        let mut a = activity(format!("s{s}_drive"), 20, 0);
        a.duration = Duration::Expanding {
            min: 1200,
            max: 3600 + rng.range(0, 4) * 600,
        };
        a.windows = Some(vec![Window {
            start: drive0,
            end: drive0 + 3600,
            preferred: None,
            cutoff: Some(drive0 + 4 * 3600),
        }]);
        a.resources = vec!["mobility".into(), "arm".into()];
        a.thermal_zones = vec!["mobility".into()];
        a.energy_rate = 110.0;
        a.peak_power = 360.0;
        a.data_rate = 0.03;
        a.requires = vec![StateRequirement {
            state: "arm".into(),
            value: "stowed".into(),
        }];
        push(&mut acts, a, &mut budget);
        let mut a = activity(format!("s{s}_navcam"), 21, 300);
        a.resources = vec!["mast".into()];
        a.data_rate = 0.4;
        a.energy_rate = 20.0;
        a.peak_power = 60.0;
        a.after = vec![Dependency {
            activity: format!("s{s}_drive"),
            meets: false,
            min_delay: Some(0),
            max_delay: Some(900),
        }];
        push(&mut acts, a, &mut budget);
        // Remote sensing (mast), some in big/small groups; then optional monitoring.
        let mut k = 0;
        while budget > 0 {
            let hours = 7.0 + rng.range(0, 11 * 60) as f64 / 60.0;
            let start = tod(s, hours);
            let dur = 120 + rng.range(0, 12) * 90;
            if rng.chance(55) {
                let mut a = activity(format!("s{s}_rs{k}"), 30 + rng.range(0, 40), dur);
                a.windows = window(
                    start,
                    (start + rng.range(1800, 6 * 3600)).min(horizon_end - dur - 600),
                    Some(start + 300),
                );
                a.resources = vec![
                    (*rng.pick(&["zcam", "supercam", "navcam", "hazcam", "rimfax", "skycam"]))
                        .into(),
                ];
                a.thermal_zones = if rng.chance(40) {
                    vec!["mast".into()]
                } else {
                    Vec::new()
                };
                a.energy_rate = 15.0 + rng.range(0, 35) as f64;
                a.peak_power = 60.0 + rng.range(0, 160) as f64;
                a.data_rate = 0.02 + rng.range(0, 20) as f64 / 100.0;
                a.mandatory = rng.chance(60);
                if rng.chance(20) {
                    a.group = Some(format!("s{s}_g{k}"));
                    let mut small = a.clone();
                    small.id = format!("s{s}_rs{k}_small");
                    small.priority = a.priority + 1;
                    small.duration = Duration::Fixed((dur / 3).max(60));
                    small.mandatory = false;
                    push(&mut acts, a, &mut budget);
                    push(&mut acts, small, &mut budget);
                } else {
                    push(&mut acts, a, &mut budget);
                }
            } else {
                let mut a = activity(
                    format!("s{s}_meda{k}"),
                    80 + rng.range(0, 15),
                    300 + rng.range(0, 6) * 100,
                );
                a.windows = window(start, (start + 3600).min(horizon_end - 1000), None);
                a.awake = AwakeMode::Any;
                a.mandatory = false;
                a.sequence_engines = if rng.chance(50) { 0 } else { 1 };
                a.energy_rate = 8.0 + rng.range(0, 10) as f64;
                a.peak_power = 20.0;
                a.data_rate = 0.01;
                push(&mut acts, a, &mut budget);
            }
            k += 1;
        }
    }
    acts.truncate(activities);
    let mut states = BTreeMap::new();
    states.insert(
        "arm".to_string(),
        StateDef {
            values: vec!["stowed".into(), "unstowed".into()],
            initial: "stowed".into(),
        },
    );
    let zone = |p: f64, m: f64, long: i64| ThermalZone {
        preheat: vec![
            PreheatEntry {
                from: 0,
                duration: long,
            },
            PreheatEntry {
                from: 9 * 3600,
                duration: long / 2,
            },
            PreheatEntry {
                from: 15 * 3600,
                duration: long / 3,
            },
            PreheatEntry {
                from: 20 * 3600,
                duration: long,
            },
        ],
        preheat_power: p,
        maintenance_power: m,
        operable: Some(vec![OperablePeriod {
            from: 3 * 3600,
            to: 22 * 3600,
        }]),
    };
    let mut zones = BTreeMap::new();
    zones.insert("arm".to_string(), zone(45.0, 15.0, 3600));
    zones.insert("mast".to_string(), zone(20.0, 8.0, 1800));
    zones.insert("mobility".to_string(), zone(60.0, 20.0, 2400));
    Plan {
        format: PLAN_FORMAT.into(),
        name: Some(format!(
            "generated: {activities} activities, {sols} sols, seed {seed}"
        )),
        horizon: Horizon {
            start: 0,
            end: horizon_end,
        },
        local_time: LocalTime {
            sol_length: sol,
            offset: 0,
            first_sol: None,
        },
        battery: Battery {
            capacity: 2400.0,
            initial: 1800.0,
            min_soc: 800.0,
        },
        power: Power {
            rtg: 110.0,
            asleep: 25.0,
            awake: 150.0,
            max_peak: Some(900.0),
        },
        sleep: Sleep {
            wakeup_duration: 300,
            shutdown_duration: 300,
            min_awake: 1800,
            min_sleep: 3600,
        },
        sequence_engines: Some(3),
        data: Data {
            capacity: Some(12000.0),
            initial: 500.0,
        },
        handover: Some(Handover {
            time: horizon_end - 3600,
            min_soc: Some(1000.0),
            max_data_volume: Some(6000.0 * sols as f64),
        }),
        states,
        thermal_zones: zones,
        activities: acts,
        execution: None,
        cycle: None,
    }
}

/// The kind of plan that [`generate_plan_with`] makes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Profile {
    /// The plans the scheduler's speed was tuned on, exactly as [`generate_plan`]
    /// makes them.
    #[default]
    Standard,
    /// Plans shaped like a real multi-sol tactical plan: about 15% of the
    /// activities without windows, several windows per activity, expanding
    /// activities, night activities, start and end effects, and tighter energy,
    /// data and handover limits. Most, not all, activities schedule.
    Realistic,
    /// The realistic plan's shapes on a battery near its minimum for days, with
    /// wider or absent windows and more preheats: about nine activities in ten
    /// fail, most in placement on the battery or handover minimum.
    Starved,
}

/// A plan of `activities` activities over `sols` sols (at least one) in the given
/// profile. [`Profile::Standard`] gives exactly [`generate_plan`]'s plan.
pub fn generate_plan_with(profile: Profile, activities: usize, sols: usize, seed: u64) -> Plan {
    match profile {
        Profile::Standard => generate_plan(activities, sols, seed),
        Profile::Realistic => Realistic::new(activities, sols, seed).plan(),
        Profile::Starved => starved(Realistic::new(activities, sols, seed).plan(), seed),
    }
}

/// The plan with a `duration_model` on `share` (0 to 1, nearest whole count) of
/// its activities that can have one: a fixed duration, no model yet, neither a
/// communication pass nor a sleep (their length is the pass's or the plan's).
/// Which activities is drawn from `seed` alone (its own random stream), so a
/// plan and a seed give the same models every time, and nothing else of the
/// plan changes. Arm work and drives (an `arm` or `mobility` resource) run long
/// more than short: actual durations from 0.6 to 1.6 times the predicted one;
/// the others from 0.8 to 1.25 times (whole seconds, the shortest at least 1).
pub fn add_duration_models(mut plan: Plan, share: f64, seed: u64) -> Plan {
    let eligible: Vec<usize> = plan
        .activities
        .iter()
        .enumerate()
        .filter(|(_, a)| {
            matches!(a.duration, Duration::Fixed(d) if d > 0)
                && a.duration_model.is_none()
                && a.comm_kind.is_none()
                && a.awake != AwakeMode::Forbidden
        })
        .map(|(i, _)| i)
        .collect();
    let share = if share.is_finite() {
        share.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let count = ((eligible.len() as f64 * share).round() as usize).min(eligible.len());
    // The first `count` of a seeded shuffle (Fisher-Yates, front to back).
    let mut rng = Rng(seed ^ 0x0D0_2A71_0000_0000);
    let mut pool = eligible;
    for k in 0..count {
        let j = rng.range(k as i64, pool.len() as i64 - 1) as usize;
        pool.swap(k, j);
    }
    for &i in &pool[..count] {
        let a = &mut plan.activities[i];
        let Duration::Fixed(d) = a.duration else {
            continue;
        };
        let long_tailed = a.resources.iter().any(|r| r == "arm" || r == "mobility");
        // (numerator, denominator) of the shortest and the longest factor.
        let ((lo_n, lo_d), (hi_n, hi_d)) = if long_tailed {
            ((3, 5), (8, 5))
        } else {
            ((4, 5), (5, 4))
        };
        a.duration_model = Some(DurationModel {
            min: (d * lo_n / lo_d).max(1),
            max: ((d * hi_n + hi_d - 1) / hi_d).max(d),
        });
    }
    plan
}

#[cfg(test)]
mod duration_model_tests {
    use super::*;

    /// Whether `a` may get a model.
    fn eligible(a: &Activity) -> bool {
        matches!(a.duration, Duration::Fixed(d) if d > 0)
            && a.comm_kind.is_none()
            && a.awake != AwakeMode::Forbidden
    }

    #[test]
    fn models_go_on_the_share_asked_with_the_spread_of_their_kind() {
        for profile in [Profile::Standard, Profile::Realistic, Profile::Starved] {
            let base = generate_plan_with(profile, 200, 2, 5);
            let candidates = base.activities.iter().filter(|a| eligible(a)).count();
            let plan = add_duration_models(base.clone(), 0.25, 5);
            crate::validate::validate(&plan).expect("valid");
            let with: Vec<(&Activity, &Activity)> = plan
                .activities
                .iter()
                .zip(&base.activities)
                .filter(|(a, _)| a.duration_model.is_some())
                .collect();
            assert_eq!(with.len(), (candidates as f64 * 0.25).round() as usize);
            for (a, b) in &with {
                assert!(eligible(a), "{} got a model", a.id);
                let (Duration::Fixed(d), Some(m)) = (a.duration, a.duration_model) else {
                    panic!("{} has a model on an expanding duration", a.id);
                };
                let long = a.resources.iter().any(|r| r == "arm" || r == "mobility");
                let (lo, hi) = if long { (0.6, 1.6) } else { (0.8, 1.25) };
                assert!(m.min >= 1 && m.min <= d && m.max >= d, "{}: {m:?}", a.id);
                assert!(
                    (m.min as f64 - lo * d as f64).abs() <= 1.0,
                    "{}: {m:?}",
                    a.id
                );
                assert!(
                    (m.max as f64 - hi * d as f64).abs() <= 1.0,
                    "{}: {m:?}",
                    a.id
                );
                // Nothing else of the activity changed.
                let mut back = (*a).clone();
                back.duration_model = None;
                assert_eq!(&back, *b);
            }
            // The rest of the plan is the plan without models.
            let mut back = plan.clone();
            for a in &mut back.activities {
                a.duration_model = None;
            }
            assert_eq!(back, base);
            // Deterministic for the seed; another seed picks other activities.
            assert_eq!(add_duration_models(base.clone(), 0.25, 5), plan);
            assert_ne!(add_duration_models(base.clone(), 0.25, 6), plan);
        }
    }

    #[test]
    fn arm_work_runs_long_more_than_short_and_the_ends_of_the_share_hold() {
        let base = generate_plan_with(Profile::Realistic, 100, 1, 2);
        assert_eq!(add_duration_models(base.clone(), 0.0, 2), base);
        let all = add_duration_models(base.clone(), 1.0, 2);
        let mut arm = 0;
        for a in &all.activities {
            assert_eq!(a.duration_model.is_some(), eligible(a), "{}", a.id);
            if let (Duration::Fixed(d), Some(m)) = (a.duration, a.duration_model)
                && a.resources.iter().any(|r| r == "arm")
            {
                arm += 1;
                assert!(m.max - d > d - m.min, "{}: {m:?} around {d}", a.id);
            }
        }
        assert!(arm > 0, "the realistic plan has arm work");
        // A share outside 0..1 is read as its nearest end.
        assert_eq!(add_duration_models(base.clone(), -1.0, 2), base);
        assert_eq!(add_duration_models(base.clone(), f64::NAN, 2), base);
        assert_eq!(add_duration_models(base, 7.0, 2), all);
    }
}

/// One hour, in seconds.
const HOUR: i64 = 3600;

/// The realistic generator: the activities so far and what places them in time.
struct Realistic {
    rng: Rng,
    /// Activities asked for.
    total: usize,
    sols: usize,
    seed: u64,
    /// Local time of day at plan time 0, in seconds.
    offset: i64,
    horizon_end: i64,
    /// Durations of the filler activities are multiplied by `scale / 100`, so that
    /// denser plans still mostly fit in a sol.
    scale: i64,
    acts: Vec<Activity>,
    /// The activity count that the current sol may reach.
    limit: usize,
}

/// Which instruments point the remote sensing mast, with their typical power (W)
/// and data rate (kbit/s, after onboard compression).
const RSM_INSTRUMENTS: [(&str, i64, i64); 5] = [
    ("zcam", 28, 60),
    ("supercam", 42, 25),
    ("navcam", 18, 80),
    ("mastcam_ir", 24, 20),
    ("skycam", 12, 10),
];

/// Contact instruments on the arm.
const ARM_INSTRUMENTS: [&str; 4] = ["pixl", "sherloc", "watson", "abrader"];

/// Engineering housekeeping, which has no fixed time.
const HOUSEKEEPING: [&str; 5] = [
    "fsw_hk",
    "dp_manage",
    "imu_cal",
    "battery_cal",
    "fault_check",
];

impl Realistic {
    fn new(total: usize, sols: usize, seed: u64) -> Self {
        let sols = sols.max(1);
        let mut rng = Rng(seed ^ 0x7EA1_157C_0000);
        let offset = rng.range(1, 59) * 60;
        let per_sol = total.div_ceil(sols).max(1);
        // About 30 activities a sol are the fixed skeleton; the rest are fillers.
        // Past about 25 fillers a sol their durations shrink (to a tenth at most),
        // so that they keep asking for about as much time and energy in all.
        let fillers = per_sol.saturating_sub(30).max(1) as i64;
        let scale = (2500 / fillers).clamp(10, 100);
        Self {
            rng,
            total,
            sols,
            seed,
            offset,
            horizon_end: MARS_SOL * sols as i64,
            scale,
            acts: Vec::with_capacity(total),
            limit: 0,
        }
    }

    /// Plan time of local time `hh:mm` on sol `s` (`hh` may pass 24).
    fn lt(&self, s: usize, hh: i64, mm: i64) -> i64 {
        s as i64 * MARS_SOL + hh * HOUR + mm * 60 - self.offset
    }

    /// A window for an activity of longest duration `dur`, kept inside the plan:
    /// it starts in the horizon, lets the activity (and its awake period) end
    /// before the horizon ends, and keeps `preferred` and `cutoff` valid.
    fn window(
        &self,
        start: i64,
        end: i64,
        preferred: Option<i64>,
        cutoff: Option<i64>,
        dur: i64,
    ) -> Window {
        let last = (self.horizon_end - dur - 1800).max(1800);
        let start = start.clamp(1800, last);
        let end = end.clamp(start, last);
        Window {
            start,
            end,
            preferred: preferred.map(|p| p.clamp(start, end)),
            cutoff: cutoff.map(|c| c.max(start + dur)),
        }
    }

    /// A filler duration: `lo..=hi` seconds, scaled down in dense plans, at least
    /// a minute, in whole minutes.
    fn filler_duration(&mut self, lo: i64, hi: i64) -> i64 {
        let d = self.rng.range(lo, hi) * self.scale / 100;
        (d / 60).max(1) * 60
    }

    /// `lo..=hi` tenths, as a decimal number.
    fn tenths(&mut self, lo: i64, hi: i64) -> f64 {
        self.rng.range(lo, hi) as f64 / 10.0
    }

    /// Adds `a` if the current sol's share is not used up; says whether it did.
    fn push(&mut self, a: Activity) -> bool {
        if self.acts.len() < self.limit {
            self.acts.push(a);
            true
        } else {
            false
        }
    }

    fn room(&self) -> bool {
        self.acts.len() < self.limit
    }

    fn plan(mut self) -> Plan {
        let per_sol = self.total.div_ceil(self.sols).max(1);
        for s in 0..self.sols {
            self.limit = self.total.min((s + 1) * per_sol);
            self.comm(s);
            self.sleep(s);
            if s == 0 || self.rng.chance(70) {
                self.arm_campaign(s);
            }
            if s == 0 || self.rng.chance(80) {
                self.drive(s);
            }
            if s % 2 == 0 {
                self.moxie(s);
            }
            self.night(s);
            let mut k = 0;
            while self.room() {
                self.filler(s, k);
                k += 1;
            }
        }
        self.acts.truncate(self.total);
        let sols = self.sols as f64;
        let horizon_end = self.horizon_end;
        let capacity = 2650.0;
        Plan {
            format: PLAN_FORMAT.into(),
            name: Some(format!(
                "generated (realistic): {} activities, {} sols, seed {}",
                self.total, self.sols, self.seed
            )),
            horizon: Horizon {
                start: 0,
                end: horizon_end,
            },
            local_time: LocalTime {
                sol_length: MARS_SOL,
                offset: self.offset,
                first_sol: None,
            },
            battery: Battery {
                capacity,
                initial: 2400.5,
                min_soc: 900.0,
            },
            power: Power {
                rtg: 108.5,
                asleep: 24.5,
                awake: 118.5,
                max_peak: Some(925.0),
            },
            sleep: Sleep {
                wakeup_duration: 420,
                shutdown_duration: 480,
                min_awake: 2400,
                min_sleep: 3600,
            },
            sequence_engines: Some(3),
            data: Data {
                capacity: Some(4500.0),
                initial: 1250.5,
            },
            handover: Some(Handover {
                time: horizon_end - 2 * HOUR,
                min_soc: Some(1250.0),
                max_data_volume: Some(3200.0 * sols),
            }),
            states: realistic_states(),
            thermal_zones: realistic_zones(),
            activities: self.acts,
            execution: None,
            cycle: None,
        }
    }

    /// Four UHF relay passes at fixed times (one of them optional) and an X-band
    /// direct-to-Earth pass that points the high-gain antenna.
    fn comm(&mut self, s: usize) {
        for (k, (orbiter, hh, mandatory)) in [
            ("ody", 3, true),
            ("tgo", 9, false),
            ("mro", 15, true),
            ("mvn", 17, true),
        ]
        .into_iter()
        .enumerate()
        {
            let mm = self.rng.range(0, 59);
            let start = self.lt(s, hh, mm);
            let dur = self.rng.range(8, 15) * 60;
            let mut a = activity(format!("s{s}_uhf_{orbiter}"), -10 + k as i64, dur);
            a.name = Some(format!("{} relay pass, sol {s}", orbiter.to_uppercase()));
            a.mandatory = mandatory;
            a.windows = Some(vec![self.window(start, start, None, None, dur)]);
            a.resources = vec!["uhf_radio".into()];
            a.comm_kind = Some("uhf".into());
            a.energy_rate = self.tenths(550, 700);
            a.peak_power = 95.0;
            a.data_rate = -(self.rng.range(4, 8) as f64) / 4.0;
            self.push(a);
        }
        let mm = self.rng.range(0, 30);
        let start = self.lt(s, 10, mm);
        let dur = self.rng.range(4, 8) * 300;
        let mut a = activity(format!("s{s}_dte"), -4, dur);
        a.name = Some(format!("X-band direct-to-Earth, sol {s}"));
        a.windows = Some(vec![self.window(
            start,
            start + 90 * 60,
            Some(start + 1800),
            Some(start + 150 * 60),
            dur,
        )]);
        a.resources = vec!["hga".into()];
        a.comm_kind = Some("xband".into());
        a.energy_rate = 85.5;
        a.peak_power = 210.0;
        a.data_rate = -0.25;
        a.effects = vec![
            effect("hga", "tracking", EffectAt::Start),
            effect("hga", "stowed", EffectAt::End),
        ];
        self.push(a);
    }

    /// A manual night sleep, and an optional midday nap.
    fn sleep(&mut self, s: usize) {
        let start = self.lt(s, 21, 0);
        let dur = self.rng.range(10, 14) * 900;
        let mut a = activity(format!("s{s}_night_sleep"), 1, dur);
        a.windows = Some(vec![self.window(start, start + 2700, None, None, dur)]);
        a.awake = AwakeMode::Forbidden;
        a.sequence_engines = 0;
        self.push(a);
        let start = self.lt(s, 12, 45);
        let dur = self.rng.range(3, 5) * 900;
        let mut a = activity(format!("s{s}_nap"), 60, dur);
        a.mandatory = false;
        a.windows = Some(vec![self.window(start, start + 5400, None, None, dur)]);
        a.awake = AwakeMode::Forbidden;
        a.sequence_engines = 0;
        self.push(a);
    }

    /// Arm unstow, contact science (one chained to the one before it), sometimes a
    /// drill core with a sealing step that meets it, and the stow.
    fn arm_campaign(&mut self, s: usize) {
        let mm = 30 + self.rng.range(0, 60);
        let arm0 = self.lt(s, 8, mm);
        let unstow = format!("s{s}_arm_unstow");
        let mut a = activity(unstow.clone(), 10, 600);
        a.windows = Some(vec![self.window(arm0, arm0 + 2 * HOUR, None, None, 600)]);
        a.resources = vec!["arm".into()];
        a.thermal_zones = vec!["arm".into()];
        a.energy_rate = 45.5;
        a.peak_power = 180.0;
        a.requires = vec![require("arm", "stowed"), require("mobility", "parked")];
        a.effects = vec![effect("arm", "unstowed", EffectAt::End)];
        if !self.push(a) {
            return;
        }
        let mut last = Vec::new();
        let contacts = 2 + self.rng.range(0, 2) as usize;
        for c in 0..contacts {
            let instrument = ARM_INSTRUMENTS[(c + s) % ARM_INSTRUMENTS.len()];
            let dur = self.rng.range(3, 12) * 600;
            let id = format!("s{s}_{instrument}_{c}");
            let mut a = activity(id.clone(), 11 + c as i64, dur);
            let open = arm0 + 600 + c as i64 * 1800;
            a.windows = Some(vec![self.window(
                arm0 + 600,
                arm0 + 7 * HOUR,
                Some(open),
                None,
                dur,
            )]);
            a.resources = vec!["arm".into(), instrument.into()];
            a.thermal_zones = vec!["arm".into()];
            a.energy_rate = self.tenths(300, 750);
            a.peak_power = self.tenths(1500, 2800);
            a.data_rate = self.rng.range(5, 50) as f64 / 1000.0;
            a.requires = vec![require("arm", "unstowed"), require("mobility", "parked")];
            a.after = vec![after(&unstow)];
            if c > 0 && self.rng.chance(50) {
                a.after.push(Dependency {
                    activity: format!("s{s}_{}_{}", ARM_INSTRUMENTS[(c - 1 + s) % 4], c - 1),
                    meets: false,
                    min_delay: Some(60),
                    max_delay: Some(3 * HOUR),
                });
            }
            a.uhf_interactions = Some(vec!["uhf".into()]);
            if self.push(a) {
                last.push(id);
            }
        }
        if s == 0 || self.rng.chance(40) {
            let core = format!("s{s}_drill_core");
            let dur = self.rng.range(4, 7) * 600;
            let mut a = activity(core.clone(), 15, dur);
            a.name = Some(format!("Drill core, sol {s}"));
            a.windows = Some(vec![self.window(
                arm0 + HOUR,
                arm0 + 6 * HOUR,
                Some(arm0 + 2 * HOUR),
                Some(self.lt(s, 17, 0)),
                dur,
            )]);
            a.resources = vec!["arm".into(), "drill".into()];
            a.thermal_zones = vec!["arm".into(), "drill".into()];
            a.energy_rate = 148.5;
            a.peak_power = 420.0;
            a.data_rate = 0.02;
            a.requires = vec![require("arm", "unstowed")];
            a.effects = vec![effect("sample_tube", "cored", EffectAt::End)];
            a.after = vec![after(&unstow)];
            a.uhf_interactions = Some(Vec::new());
            if self.push(a) {
                let mut a = activity(format!("s{s}_seal"), 15, 900);
                a.resources = vec!["sha".into()];
                a.energy_rate = 62.5;
                a.peak_power = 140.0;
                a.requires = vec![require("sample_tube", "cored")];
                a.effects = vec![effect("sample_tube", "sealed", EffectAt::End)];
                a.after = vec![Dependency {
                    activity: core.clone(),
                    meets: true,
                    min_delay: None,
                    max_delay: None,
                }];
                self.push(a);
                last.push(core);
            }
        }
        let mut a = activity(format!("s{s}_arm_stow"), 17, 600);
        a.windows = Some(vec![self.window(
            arm0 + HOUR,
            arm0 + 9 * HOUR,
            None,
            Some(self.lt(s, 20, 0)),
            600,
        )]);
        a.resources = vec!["arm".into()];
        a.thermal_zones = vec!["arm".into()];
        a.energy_rate = 45.5;
        a.peak_power = 180.0;
        a.effects = vec![effect("arm", "stowed", EffectAt::End)];
        a.after = last.iter().map(|id| after(id)).collect();
        self.push(a);
    }

    /// An expanding drive (up to four times its minimum) in one of two windows,
    /// then post-drive imaging.
    fn drive(&mut self, s: usize) {
        let min = self.rng.range(3, 5) * 600;
        let max = min * self.rng.range(2, 4);
        let drive = format!("s{s}_drive");
        let mut a = activity(drive.clone(), 20, 0);
        a.duration = Duration::Expanding { min, max };
        let w1 = self.lt(s, 13, 0);
        let w2 = self.lt(s, 15, 0);
        a.windows = Some(vec![
            self.window(
                w1,
                w1 + 90 * 60,
                Some(w1 + 900),
                Some(self.lt(s, 17, 0)),
                min,
            ),
            self.window(w2, w2 + HOUR, None, Some(self.lt(s, 18, 30)), min),
        ]);
        a.resources = vec!["mobility".into()];
        a.thermal_zones = vec!["mobility".into()];
        a.energy_rate = 112.5;
        a.peak_power = 390.0;
        a.data_rate = 0.05;
        a.requires = vec![require("arm", "stowed"), require("hga", "stowed")];
        a.effects = vec![
            effect("mobility", "driving", EffectAt::Start),
            effect("mobility", "parked", EffectAt::End),
        ];
        a.uhf_interactions = Some(Vec::new());
        if !self.push(a) {
            return;
        }
        let mut a = activity(format!("s{s}_navcam_postdrive"), 21, 600);
        a.resources = vec!["rsm".into(), "navcam".into()];
        a.energy_rate = 18.5;
        a.peak_power = 70.0;
        a.data_rate = 0.25;
        a.requires = vec![require("mobility", "parked")];
        a.after = vec![Dependency {
            activity: drive.clone(),
            meets: false,
            min_delay: Some(0),
            max_delay: Some(900),
        }];
        self.push(a);
        let min = self.rng.range(2, 3) * 600;
        let mut a = activity(format!("s{s}_zcam_postdrive"), 22, 0);
        if self.rng.chance(50) {
            a.duration = Duration::Expanding { min, max: min * 3 };
        } else {
            a.duration = Duration::Fixed(min);
        }
        a.mandatory = false;
        a.resources = vec!["rsm".into(), "zcam".into()];
        a.thermal_zones = vec!["rsm".into()];
        a.energy_rate = 27.5;
        a.peak_power = 85.0;
        a.data_rate = 0.1;
        a.requires = vec![require("mobility", "parked")];
        a.after = vec![Dependency {
            activity: drive,
            meets: false,
            min_delay: Some(600),
            max_delay: Some(3 * HOUR),
        }];
        self.push(a);
    }

    /// MOXIE: an hour at high power after a long preheat, optional.
    fn moxie(&mut self, s: usize) {
        let start = self.lt(s, 8, 0);
        let mut a = activity(format!("s{s}_moxie"), 35, HOUR);
        a.name = Some(format!("MOXIE oxygen run, sol {s}"));
        a.mandatory = false;
        a.windows = Some(vec![self.window(
            start,
            start + 3 * HOUR,
            Some(start + HOUR),
            None,
            HOUR,
        )]);
        a.resources = vec!["moxie".into()];
        a.thermal_zones = vec!["moxie".into()];
        a.energy_rate = 212.5;
        a.peak_power = 310.0;
        a.data_rate = 0.005;
        self.push(a);
    }

    /// Night environmental monitoring, rover asleep or not; one is expanding.
    fn night(&mut self, s: usize) {
        for k in 0..3 {
            let start = self.lt(s, 22, 0) + k * 2 * HOUR + self.rng.range(0, 30) * 60;
            let mut a = activity(format!("s{s}_meda_night{k}"), 70 + k, 1200);
            if k == 0 && self.rng.chance(50) {
                a.duration = Duration::Expanding {
                    min: 1200,
                    max: 1200 * self.rng.range(2, 4),
                };
            }
            a.mandatory = false;
            a.windows = Some(vec![self.window(
                start,
                start + HOUR,
                None,
                None,
                a.duration.max(),
            )]);
            a.resources = vec!["meda".into()];
            a.awake = AwakeMode::Any;
            a.sequence_engines = 0;
            a.energy_rate = 9.5;
            a.peak_power = 15.0;
            a.data_rate = 0.002;
            self.push(a);
        }
    }

    /// One filler: remote sensing on the mast (sometimes as a group of
    /// alternatives), housekeeping without a window, or atmospheric monitoring.
    fn filler(&mut self, s: usize, k: usize) {
        let id = format!("s{s}_f{k}");
        let roll = self.rng.range(0, 99);
        let mut a = if roll < 55 {
            self.remote_sensing(s, id)
        } else if roll < 70 {
            self.housekeeping(id)
        } else {
            self.atmosphere(s, id)
        };
        // Expanding: about 4% of the fillers, up to four times the minimum.
        if a.awake != AwakeMode::Forbidden && self.rng.chance(4) {
            let min = a.duration.min();
            let max = (min * self.rng.range(2, 4)).min(4 * HOUR).max(min);
            a.duration = Duration::Expanding { min, max };
        }
        // Communication constraints.
        let roll = self.rng.range(0, 99);
        if roll < 8 {
            a.uhf_interactions = Some(Vec::new());
        } else if roll < 18 {
            a.uhf_interactions = Some(vec!["uhf".into()]);
        } else if roll < 22 {
            a.uhf_interactions = Some(vec!["xband".into()]);
        }
        // A dependency on an earlier filler of this sol (12%), 1 in 6 of them `meets`.
        if k > 0 && self.rng.chance(12) {
            let back = self.rng.range(1, k.min(5) as i64) as usize;
            let target = format!("s{s}_f{}", k - back);
            let placed = self.acts.iter().rev().take(12).find(|t| t.id == target);
            if let Some(target_priority) = placed.map(|t| t.priority) {
                a.priority = a.priority.max(target_priority + 1);
                a.after = vec![if self.rng.chance(17) {
                    Dependency {
                        activity: target,
                        meets: true,
                        min_delay: None,
                        max_delay: None,
                    }
                } else {
                    Dependency {
                        activity: target,
                        meets: false,
                        min_delay: Some(self.rng.range(0, 10) * 60),
                        max_delay: if self.rng.chance(50) {
                            Some(self.rng.range(1, 6) * 1800)
                        } else {
                            None
                        },
                    }
                }];
            }
        }
        // Groups of alternatives: a full, a reduced and sometimes a minimal version.
        if a.resources.iter().any(|r| r == "rsm") && a.after.is_empty() && self.rng.chance(12) {
            let group = format!("s{s}_g{k}");
            a.group = Some(group);
            let versions = if self.rng.chance(40) { 3 } else { 2 };
            let mut alternatives = Vec::new();
            for v in 1..versions {
                let mut alt = a.clone();
                alt.id = format!("{}_v{v}", a.id);
                alt.priority = a.priority + v;
                alt.mandatory = false;
                alt.duration = Duration::Fixed((a.duration.min() / (2 * v)).max(60));
                alt.data_rate = a.data_rate / 2.0;
                alternatives.push(alt);
            }
            self.push(a);
            for alt in alternatives {
                self.push(alt);
            }
        } else {
            self.push(a);
        }
    }

    /// Imaging or spectroscopy from the remote sensing mast.
    fn remote_sensing(&mut self, s: usize, id: String) -> Activity {
        let (instrument, power, kbps) = *self.rng.pick(&RSM_INSTRUMENTS);
        let dur = if self.rng.chance(75) {
            self.filler_duration(180, 1200)
        } else {
            self.filler_duration(1200, 5400)
        };
        let mut a = activity(id, 30 + self.rng.range(0, 40), dur);
        a.mandatory = self.rng.chance(60);
        a.windows = self.daytime_windows(s, dur);
        a.resources = vec!["rsm".into(), instrument.into()];
        if self.rng.chance(35) {
            a.thermal_zones = vec!["rsm".into()];
        }
        a.sequence_engines = if self.rng.chance(6) { 2 } else { 1 };
        // In tenths of a watt, so that the numbers stay plain decimals.
        let energy = power * 10 + self.rng.range(-50, 80);
        a.energy_rate = energy as f64 / 10.0;
        a.peak_power = (energy + self.rng.range(4, 30) * 50) as f64 / 10.0;
        a.data_rate = (kbps + self.rng.range(0, kbps)) as f64 / 1000.0;
        if self.rng.chance(50) {
            a.requires = vec![require("mobility", "parked")];
        }
        if self.rng.chance(25) {
            a.name = Some(format!("{instrument} observation"));
        }
        a
    }

    /// Engineering work with no fixed time: no windows at all, mostly.
    fn housekeeping(&mut self, id: String) -> Activity {
        let what = *self.rng.pick(&HOUSEKEEPING);
        let dur = self.filler_duration(120, 900);
        let mut a = activity(id, 40 + self.rng.range(0, 40), dur);
        a.name = Some(what.replace('_', " "));
        a.mandatory = self.rng.chance(70);
        a.resources = vec![what.into()];
        let energy = self.rng.range(40, 180);
        a.energy_rate = energy as f64 / 10.0;
        a.peak_power = (energy + 200) as f64 / 10.0;
        a.data_rate = self.rng.range(1, 10) as f64 / 1000.0;
        if self.rng.chance(20) {
            a.awake = AwakeMode::Any;
            a.sequence_engines = 0;
        }
        if self.rng.chance(40) {
            // Some are tied to the afternoon after all.
            let start = self.lt(0, 12, 0);
            a.windows = self.multi_sol_windows(start, 4 * HOUR, dur);
        }
        a
    }

    /// Atmospheric and environmental monitoring: sky images, MEDA, RIMFAX
    /// soundings; many with the rover asleep or awake alike.
    fn atmosphere(&mut self, s: usize, id: String) -> Activity {
        let any = self.rng.chance(55);
        let dur = if any {
            self.filler_duration(900, 7200)
        } else {
            self.filler_duration(300, 1500)
        };
        let mut a = activity(id, 45 + self.rng.range(0, 45), dur);
        a.mandatory = self.rng.chance(40);
        if any {
            a.awake = AwakeMode::Any;
            a.sequence_engines = 0;
            a.resources = vec![(*self.rng.pick(&["meda", "rimfax", "rad"])).into()];
            let energy = self.rng.range(40, 150);
            a.energy_rate = energy as f64 / 10.0;
            a.peak_power = (energy + 50) as f64 / 10.0;
            a.data_rate = self.rng.range(1, 20) as f64 / 1000.0;
            if self.rng.chance(20) {
                a.windows = None;
            } else {
                let hh = self.rng.range(0, 23);
                let start = self.lt(s, hh, 0);
                let len = self.rng.range(1, 4) * HOUR;
                a.windows = Some(vec![self.window(start, start + len, None, None, dur)]);
            }
        } else {
            // Sky images at dawn or dusk, on any sol of the plan.
            a.resources = vec!["skycam".into()];
            let energy = self.rng.range(120, 260);
            a.energy_rate = energy as f64 / 10.0;
            a.peak_power = (energy + 400) as f64 / 10.0;
            a.data_rate = self.rng.range(20, 80) as f64 / 1000.0;
            let hh = if self.rng.chance(50) { 7 } else { 17 };
            let start = self.lt(0, hh, 0);
            a.windows = self.multi_sol_windows(start, 90 * 60, dur);
        }
        a
    }

    /// Daytime windows for mast work on sol `s`: one window (78%), one per sol of
    /// the plan from a random sol on (12%), or none at all (10%); preferred times
    /// and sometimes cutoffs.
    fn daytime_windows(&mut self, s: usize, dur: i64) -> Option<Vec<Window>> {
        let roll = self.rng.range(0, 99);
        if roll < 10 {
            return None;
        }
        let start = self.lt(s, 7, 30) + self.rng.range(0, 11 * 60) * 60;
        let len = self.rng.range(1, 10) * 1800;
        if roll < 22 {
            let first = self.lt(0, 7, 30) + (start - self.lt(s, 7, 30));
            return self.multi_sol_windows(first, len, dur);
        }
        let preferred = start + self.rng.range(0, len / 60) * 60;
        let cutoff = self
            .rng
            .chance(30)
            .then(|| start + len + dur / 2 + self.rng.range(0, 4) * 900);
        Some(vec![self.window(
            start,
            start + len,
            Some(preferred),
            cutoff,
            dur,
        )])
    }

    /// One window per sol at the same local time, starting on a random sol, each
    /// with a preferred time in its middle and a cutoff.
    fn multi_sol_windows(&mut self, first: i64, len: i64, dur: i64) -> Option<Vec<Window>> {
        let from = self.rng.range(0, self.sols as i64 - 1);
        let windows = (from..self.sols as i64)
            .map(|sol| {
                let start = first + sol * MARS_SOL;
                self.window(
                    start,
                    start + len,
                    Some(start + len / 2),
                    Some(start + len + dur),
                    dur,
                )
            })
            .collect();
        Some(windows)
    }
}

/// The starved profile: `plan`, a realistic plan, on a battery near its minimum
/// for days (a weak RTG, little charge above `min_soc`, a handover minimum just
/// above it), with `min_sleep` but no `min_awake`, and its fillers made harder to
/// place on energy: a third lose their windows, a third get windows six hours
/// wider (without cutoffs), and about a third of the awake ones are preheated in a
/// zone with operable periods. Its own random stream, so the realistic profile is
/// unchanged.
fn starved(mut plan: Plan, seed: u64) -> Plan {
    let mut rng = Rng(seed ^ 0x05_7A2F_ED00_0000);
    plan.name = plan.name.map(|n| n.replacen("(realistic)", "(starved)", 1));
    plan.battery = Battery {
        capacity: 2650.0,
        initial: 1020.5,
        min_soc: 950.0,
    };
    plan.power.rtg = 52.5;
    plan.sleep.min_awake = 0;
    if let Some(h) = plan.handover.as_mut() {
        h.min_soc = Some(1010.0);
    }
    let horizon_end = plan.horizon.end;
    for a in &mut plan.activities {
        if !a.id.contains("_f") {
            continue;
        }
        let longest = a.duration.max();
        let last = (horizon_end - longest - 1800).max(1800);
        match rng.range(0, 2) {
            0 => a.windows = None,
            1 => {
                if let Some(ws) = a.windows.as_mut() {
                    for w in ws {
                        w.end = (w.end + 6 * HOUR).min(last).max(w.start);
                        w.cutoff = None;
                    }
                }
            }
            _ => {}
        }
        if a.awake == AwakeMode::Required && a.thermal_zones.is_empty() && rng.chance(35) {
            let zone = if rng.chance(50) { "arm" } else { "mobility" };
            a.thermal_zones = vec![zone.into()];
        }
    }
    plan
}

fn require(state: &str, value: &str) -> StateRequirement {
    StateRequirement {
        state: state.into(),
        value: value.into(),
    }
}

fn effect(state: &str, value: &str, at: EffectAt) -> StateEffect {
    StateEffect {
        state: state.into(),
        value: value.into(),
        at,
    }
}

fn after(id: &str) -> Dependency {
    Dependency {
        activity: id.into(),
        meets: false,
        min_delay: None,
        max_delay: None,
    }
}

fn realistic_states() -> BTreeMap<String, StateDef> {
    let state = |values: &[&str]| StateDef {
        values: values.iter().map(|v| (*v).into()).collect(),
        initial: values[0].into(),
    };
    let mut states = BTreeMap::new();
    states.insert("arm".into(), state(&["stowed", "unstowed"]));
    states.insert("hga".into(), state(&["stowed", "tracking"]));
    states.insert("mobility".into(), state(&["parked", "driving"]));
    states.insert("sample_tube".into(), state(&["empty", "cored", "sealed"]));
    states
}

/// Five heated zones. Preheats are longest in the cold early morning and nil in
/// the warm afternoon; most heaters may only start in daytime, the drill's also
/// around midnight (a period that wraps), MOXIE's overnight.
fn realistic_zones() -> BTreeMap<String, ThermalZone> {
    let table = |rows: &[(i64, i64)]| {
        rows.iter()
            .map(|&(hh, duration)| PreheatEntry {
                from: hh * HOUR,
                duration,
            })
            .collect()
    };
    let period = |from: i64, to: i64| OperablePeriod {
        from: from * HOUR,
        to: to * HOUR,
    };
    let mut zones = BTreeMap::new();
    zones.insert(
        "arm".into(),
        ThermalZone {
            preheat: table(&[(0, 5400), (7, 3600), (11, 1200), (16, 0), (19, 3600)]),
            preheat_power: 48.5,
            maintenance_power: 15.5,
            operable: Some(vec![period(5, 20)]),
        },
    );
    zones.insert(
        "drill".into(),
        ThermalZone {
            // Rows in any order: the format allows it.
            preheat: table(&[(10, 1800), (0, 3600), (20, 3600)]),
            preheat_power: 35.0,
            maintenance_power: 12.5,
            operable: Some(vec![period(22, 2), period(6, 18)]),
        },
    );
    zones.insert(
        "mobility".into(),
        ThermalZone {
            preheat: table(&[(0, 4800), (9, 2400), (13, 1200), (18, 3600)]),
            preheat_power: 62.5,
            maintenance_power: 22.5,
            operable: Some(vec![period(8, 19)]),
        },
    );
    zones.insert(
        "moxie".into(),
        ThermalZone {
            preheat: table(&[(0, 7200), (12, 3600)]),
            preheat_power: 65.5,
            maintenance_power: 30.0,
            operable: Some(vec![period(20, 10)]),
        },
    );
    zones.insert(
        "rsm".into(),
        ThermalZone {
            preheat: table(&[(0, 1800), (8, 900), (12, 0), (17, 1200)]),
            preheat_power: 18.5,
            maintenance_power: 6.5,
            operable: None,
        },
    );
    zones
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How many activities of `plan` the scheduler places.
    fn scheduled(plan: &Plan) -> usize {
        crate::scheduler::schedule(plan)
            .expect("schedules")
            .steps
            .iter()
            .filter(|x| x.outcome.placement().is_some())
            .count()
    }

    #[test]
    fn generated_plans_are_valid_and_deterministic() {
        for (n, sols) in [(5, 1), (100, 1), (300, 3)] {
            let plan = generate_plan(n, sols, 7);
            assert_eq!(plan.activities.len(), n);
            crate::validate::validate(&plan).expect("valid");
            assert_eq!(plan, generate_plan(n, sols, 7));
            let scheduled = scheduled(&plan);
            assert!(scheduled * 2 >= n, "{scheduled} of {n} scheduled");
        }
        assert_ne!(generate_plan(50, 1, 1), generate_plan(50, 1, 2));
    }

    /// Counts of what a plan uses, for the realistic profile's tests.
    fn count(plan: &Plan, f: impl Fn(&Activity) -> bool) -> usize {
        plan.activities.iter().filter(|a| f(a)).count()
    }

    #[test]
    fn standard_profile_is_generate_plan() {
        assert_eq!(
            generate_plan_with(Profile::Standard, 120, 2, 9),
            generate_plan(120, 2, 9)
        );
        assert_eq!(Profile::default(), Profile::Standard);
    }

    #[test]
    fn realistic_plans_load_and_use_every_feature() {
        for (n, sols, seed) in [
            (50, 1, 1),
            (50, 1, 4),
            (120, 2, 2),
            (300, 3, 3),
            (300, 3, 7),
        ] {
            let plan = generate_plan_with(Profile::Realistic, n, sols, seed);
            let what = format!("{n} activities, {sols} sols, seed {seed}");
            assert_eq!(plan.activities.len(), n, "{what}");
            assert_eq!(
                plan,
                generate_plan_with(Profile::Realistic, n, sols, seed),
                "{what}"
            );
            // Through the text, as `solscope generate` prints it.
            let text = serde_json::to_string_pretty(&plan).expect("serialises");
            let loaded = crate::load::load_plan(&text).expect(&what);
            for w in &loaded.warnings {
                // Only the step-order remark about optional activities is expected:
                // no rounded numbers, no dependency on a later step, no requirement
                // that nothing satisfies.
                assert!(
                    w.message.contains("optional activity"),
                    "{what}: unexpected warning {w}"
                );
            }
            // Plan-level features.
            assert!(plan.local_time.offset > 0, "{what}");
            let sleep = plan.sleep;
            assert!(sleep.min_awake > 0 && sleep.min_sleep > 0, "{what}");
            assert!(
                sleep.wakeup_duration > 0 && sleep.shutdown_duration > 0,
                "{what}"
            );
            assert!(plan.power.max_peak.is_some(), "{what}");
            assert!(plan.sequence_engines.is_some(), "{what}");
            assert!(
                plan.data.capacity.is_some() && plan.data.initial > 0.0,
                "{what}"
            );
            let handover = plan.handover.expect("handover");
            assert!(handover.min_soc.is_some() && handover.max_data_volume.is_some());
            assert!(plan.states.len() >= 3, "{what}");
            assert!(plan.thermal_zones.len() >= 3, "{what}");
            assert!(
                plan.thermal_zones
                    .values()
                    .any(|z| z.preheat.len() > 1 && z.preheat.iter().any(|p| p.duration == 0)),
                "{what}"
            );
            assert!(
                plan.thermal_zones.values().any(|z| z
                    .operable
                    .as_ref()
                    .is_some_and(|o| o.iter().any(|p| p.from > p.to))),
                "{what}: an operable period wrapping past midnight"
            );
            // Durations: expanding ones (about 5%, some awake-required), max <= 4x min.
            let expanding = count(&plan, |a| matches!(a.duration, Duration::Expanding { .. }));
            assert!(
                expanding >= 2 && expanding * 100 <= n * if n < 100 { 12 } else { 8 },
                "{what}: {expanding} expanding"
            );
            assert!(
                count(&plan, |a| a.duration.max() > a.duration.min()
                    && a.awake == AwakeMode::Required)
                    >= 1,
                "{what}"
            );
            assert!(
                plan.activities
                    .iter()
                    .all(|a| a.duration.max() <= 4 * a.duration.min())
            );
            assert!(
                plan.activities
                    .iter()
                    .all(|a| a.duration.max() <= 4 * HOUR && a.duration.min() >= 60),
                "{what}"
            );
            // Windows: about 15% without, several windows, preferred times, cutoffs.
            let windowless = count(&plan, |a| a.windows.is_none());
            assert!(
                (n * 8..=n * 25).contains(&(windowless * 100)),
                "{what}: {windowless} without windows"
            );
            let windows = |a: &Activity| a.windows.as_deref().unwrap_or_default().to_vec();
            if sols > 1 {
                assert!(count(&plan, |a| windows(a).len() > 1) >= 1, "{what}");
            }
            assert!(count(&plan, |a| windows(a).iter().any(|w| w.preferred.is_some())) >= 1);
            assert!(count(&plan, |a| windows(a).iter().any(|w| w.cutoff.is_some())) >= 1);
            // Wake state, heating, states, dependencies, groups, comms.
            for mode in [AwakeMode::Required, AwakeMode::Forbidden, AwakeMode::Any] {
                assert!(count(&plan, |a| a.awake == mode) >= 1, "{what}: {mode:?}");
            }
            assert!(count(&plan, |a| !a.thermal_zones.is_empty()) >= 3, "{what}");
            assert!(count(&plan, |a| !a.requires.is_empty()) >= 3, "{what}");
            for at in [EffectAt::Start, EffectAt::End] {
                assert!(
                    count(&plan, |a| a.effects.iter().any(|e| e.at == at)) >= 1,
                    "{what}"
                );
            }
            assert!(
                count(&plan, |a| a.after.iter().any(|d| d.meets)) >= 1,
                "{what}"
            );
            assert!(
                count(&plan, |a| a
                    .after
                    .iter()
                    .any(|d| d.min_delay.is_some() || d.max_delay.is_some()))
                    >= 1,
                "{what}"
            );
            let mut groups: BTreeMap<&str, usize> = BTreeMap::new();
            for a in &plan.activities {
                if let Some(g) = &a.group {
                    *groups.entry(g).or_default() += 1;
                }
            }
            assert!(
                groups.values().any(|&members| members >= 2),
                "{what}: {groups:?}"
            );
            for kind in ["uhf", "xband"] {
                assert!(
                    count(&plan, |a| a.comm_kind.as_deref() == Some(kind)) >= 1,
                    "{what}"
                );
            }
            assert!(
                count(&plan, |a| a
                    .uhf_interactions
                    .as_ref()
                    .is_some_and(Vec::is_empty))
                    >= 1
            );
            assert!(
                count(&plan, |a| a
                    .uhf_interactions
                    .as_ref()
                    .is_some_and(|k| !k.is_empty()))
                    >= 1
            );
            assert!(count(&plan, |a| !a.mandatory) >= 1 && count(&plan, |a| a.mandatory) >= 1);
            assert!(count(&plan, |a| a.sequence_engines == 0) >= 1, "{what}");
            assert!(
                count(&plan, |a| a.data_rate < 0.0) >= 1
                    && count(&plan, |a| a.data_rate > 0.0) >= 1
            );
            // Times: every sol has activities, and activities last minutes to hours.
            let sol_of = |a: &Activity| windows(a).first().map(|w| w.start / MARS_SOL);
            for s in 0..sols as i64 {
                assert!(
                    count(&plan, |a| sol_of(a) == Some(s)) >= 5,
                    "{what}: sol {s}"
                );
            }
        }
    }

    /// Starved plans are valid (no warning but the step-order remark), keep
    /// the realistic plan's activities, and fail as the profile says: at least
    /// seven activities in ten (about nine at 333 a sol), most of those in
    /// placement with starts rejected on energy.
    #[test]
    fn starved_plans_mostly_fail_on_energy() {
        use crate::scheduler::{FailurePhase, Outcome};
        for (n, sols, seed) in [(300, 3, 1), (300, 3, 5), (1000, 3, 2)] {
            let what = format!("{n} activities, {sols} sols, seed {seed}");
            let plan = generate_plan_with(Profile::Starved, n, sols, seed);
            assert_eq!(plan, generate_plan_with(Profile::Starved, n, sols, seed));
            let realistic = generate_plan_with(Profile::Realistic, n, sols, seed);
            let ids = |p: &Plan| {
                p.activities
                    .iter()
                    .map(|a| a.id.clone())
                    .collect::<Vec<_>>()
            };
            assert_eq!(ids(&plan), ids(&realistic), "{what}");
            assert_ne!(plan, realistic, "{what}");
            let text = serde_json::to_string_pretty(&plan).expect("serialises");
            let loaded = crate::load::load_plan(&text).expect(&what);
            for w in &loaded.warnings {
                assert!(
                    w.message.contains("optional activity"),
                    "{what}: unexpected warning {w}"
                );
            }
            assert_eq!(plan.sleep.min_awake, 0, "{what}");
            assert!(plan.sleep.min_sleep > 0, "{what}");
            let sched = crate::scheduler::schedule(&plan).expect("schedules");
            let failed = sched
                .steps
                .iter()
                .filter(|x| matches!(x.outcome, Outcome::Failed(_)))
                .count();
            let on_energy = sched
                .steps
                .iter()
                .filter(|x| {
                    x.outcome == Outcome::Failed(FailurePhase::Placement)
                        && x.rejected.soc.is_some()
                })
                .count();
            assert!(failed * 100 >= n * 70, "{what}: {failed} failed");
            assert!(
                on_energy * 100 >= failed * 60,
                "{what}: {on_energy} of {failed} on energy"
            );
        }
    }

    #[test]
    fn realistic_plans_mostly_schedule() {
        for (n, sols, seed) in [(50, 1, 2), (100, 1, 4), (300, 3, 1), (300, 3, 4)] {
            let plan = generate_plan_with(Profile::Realistic, n, sols, seed);
            let scheduled = scheduled(&plan);
            assert!(
                (n * 60..=n * 90).contains(&(scheduled * 100)),
                "{n} activities, {sols} sols, seed {seed}: {scheduled} scheduled"
            );
        }
    }
}

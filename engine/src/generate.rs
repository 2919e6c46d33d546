//! Random but realistic plans, for stress tests and benchmarks: per sol, relay and
//! direct-to-Earth passes, a manual night sleep, arm campaigns with state changes
//! and heating, an expanding drive with post-drive imaging, remote sensing with
//! big/small groups, and optional environmental monitoring. Deterministic per seed.

use std::collections::BTreeMap;

use crate::model::{
    Activity, AwakeMode, Battery, Data, Dependency, Duration, EffectAt, Handover, Horizon,
    LocalTime, MARS_SOL, OperablePeriod, PLAN_FORMAT, Plan, Power, PreheatEntry, Sleep, StateDef,
    StateEffect, StateRequirement, ThermalZone, Window,
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_plans_are_valid_and_deterministic() {
        for (n, sols) in [(5, 1), (100, 1), (300, 3)] {
            let plan = generate_plan(n, sols, 7);
            assert_eq!(plan.activities.len(), n);
            crate::validate::validate(&plan).expect("valid");
            assert_eq!(plan, generate_plan(n, sols, 7));
            let s = crate::scheduler::schedule(&plan).expect("schedules");
            let scheduled = s
                .steps
                .iter()
                .filter(|x| x.outcome.placement().is_some())
                .count();
            assert!(scheduled * 2 >= n, "{scheduled} of {n} scheduled");
        }
        assert_ne!(generate_plan(50, 1, 1), generate_plan(50, 1, 2));
    }
}

//! The breakpoints of a capped integrator (a [`RateTimeline`]'s levels), stored
//! in chunks so that a change to the rate re-derives only what it changes.
//!
//! A placement changes the rate on a short span, yet every level after it moves:
//! down by the deficit it leaves, less what the unchanged trajectory loses to the
//! cap afterwards (the charge a full battery would have thrown away). Stored
//! flat, every level after the change was rewritten, O(n) per placement. Here
//! each chunk holds its levels and losses relative to an offset, with its own
//! prefix and suffix minima (which a shift leaves as they are), so a shift costs
//! O(1) per chunk; only the chunks where the cap absorbs part of a deficit, or
//! where a surplus (a higher level) has not yet met the old trajectory, are
//! rewritten point by point.
//!
//! The levels never start above the cap (a battery's initial charge is at most
//! its capacity; data volume starts at or below its cap of 0): above it the old
//! trajectory would lose charge the new one does not, and the deficit rule
//! below would not hold. [`Points::new`] asserts it in debug builds.
//!
//! [`RateTimeline`]: super::RateTimeline

use super::StepFn;
use super::minimum::MinTree;

/// Points per chunk when a group of points is cut into chunks (a chunk holds
/// fewer than `2 * CHUNK` points; one can hold fewer than `CHUNK` after points
/// coalesce away, as chunks are not merged). Small in tests and debug builds, so
/// that the chunk boundaries are crossed by small plans.
const CHUNK: usize = if cfg!(test) {
    3
} else if cfg!(debug_assertions) {
    8
} else {
    64
};

/// Level after running at `rate` for `dt` seconds from `level`, capped at `cap`.
pub(super) fn advance(level: i128, rate: i64, dt: i64, cap: i128) -> i128 {
    let next = level + i128::from(rate) * i128::from(dt);
    if rate > 0 {
        next.min(cap.max(level))
    } else {
        next
    }
}

/// `(minimum, first index)`, the earlier index winning ties.
type Min = (i128, usize);

/// A chunk's summaries hold local indices, not values: a point's index in
/// one byte (a chunk holds fewer than `2 * CHUNK <= 256` points), its value
/// read back from the chunk. A summary is rewritten with every chunk
/// rewrite (at least one per placement), so its size is what it costs.
type Local = u8;
const _: () = assert!(2 * CHUNK <= Local::MAX as usize + 1);

/// A run of consecutive points. `level` and `waste` are stored less the chunk's
/// offsets; the minima are over the stored values (a shift moves them all), and
/// are kept as the local index of the first point attaining them.
#[derive(Clone, Debug)]
struct Chunk {
    /// Each point's time.
    times: Vec<i64>,
    /// Rate from each point to the next (0 for the domain end).
    rates: Vec<i64>,
    /// Each point's level, less `off_level`.
    levels: Vec<i128>,
    /// The charge lost to the cap before each point, less `off_waste`.
    wastes: Vec<i128>,
    /// What every stored level lacks.
    off_level: i128,
    /// What every stored waste lacks.
    off_waste: i128,
    /// The first local index of the min of `levels[..=o]`.
    prefix: Vec<Local>,
    /// The first local index of the min of `levels[o..]`.
    suffix: Vec<Local>,
    /// The same over `level + waste` (the uncapped trajectory).
    unc_prefix: Vec<Local>,
    unc_suffix: Vec<Local>,
}

impl Chunk {
    /// A chunk of these points (absolute values), summarised.
    fn new(times: Vec<i64>, rates: Vec<i64>, levels: Vec<i128>, wastes: Vec<i128>) -> Self {
        let mut c = Self {
            times,
            rates,
            levels,
            wastes,
            off_level: 0,
            off_waste: 0,
            prefix: Vec::new(),
            suffix: Vec::new(),
            unc_prefix: Vec::new(),
            unc_suffix: Vec::new(),
        };
        c.summarise();
        c
    }

    /// The number of points.
    fn len(&self) -> usize {
        self.times.len()
    }

    /// Point `o`'s level.
    fn level(&self, o: usize) -> i128 {
        self.levels[o] + self.off_level
    }

    /// Point `o`'s waste.
    fn waste(&self, o: usize) -> i128 {
        self.wastes[o] + self.off_waste
    }

    /// Sets point `o`'s level and waste (absolute); [`Self::summarise`] after.
    fn set(&mut self, o: usize, level: i128, waste: i128) {
        self.levels[o] = level - self.off_level;
        self.wastes[o] = waste - self.off_waste;
    }

    /// Recomputes the minima (in place: a chunk is summarised after every
    /// rewrite).
    fn summarise(&mut self) {
        /// `(prefix, suffix)` minima of `value(0..n)`, first index on ties.
        fn fill(
            prefix: &mut Vec<Local>,
            suffix: &mut Vec<Local>,
            n: usize,
            value: impl Fn(usize) -> i128,
        ) {
            prefix.clear();
            let mut best = (i128::MAX, 0);
            for o in 0..n {
                let v = value(o);
                if v < best.0 {
                    best = (v, o as Local);
                }
                prefix.push(best.1);
            }
            suffix.clear();
            suffix.resize(n, 0);
            let mut best = (i128::MAX, 0);
            for o in (0..n).rev() {
                let v = value(o);
                if v <= best.0 {
                    best = (v, o as Local);
                }
                suffix[o] = best.1;
            }
        }
        let n = self.len();
        let Self {
            levels,
            wastes,
            prefix,
            suffix,
            unc_prefix,
            unc_suffix,
            ..
        } = self;
        fill(prefix, suffix, n, |o| levels[o]);
        fill(unc_prefix, unc_suffix, n, |o| levels[o] + wastes[o]);
    }

    /// Moves the points out with their absolute values (the chunk is left
    /// empty, its summaries' storage kept for [`Self::refill`]).
    fn take(&mut self) -> Flat {
        let (dl, dw) = (self.off_level, self.off_waste);
        let mut flat = Flat {
            times: std::mem::take(&mut self.times),
            rates: std::mem::take(&mut self.rates),
            levels: std::mem::take(&mut self.levels),
            wastes: std::mem::take(&mut self.wastes),
        };
        if dl != 0 {
            flat.levels.iter_mut().for_each(|l| *l += dl);
        }
        if dw != 0 {
            flat.wastes.iter_mut().for_each(|w| *w += dw);
        }
        (self.off_level, self.off_waste) = (0, 0);
        flat
    }

    /// Puts `flat`'s points back (absolute values) and summarises them.
    fn refill(&mut self, flat: Flat) {
        (self.times, self.rates, self.levels, self.wastes) =
            (flat.times, flat.rates, flat.levels, flat.wastes);
        (self.off_level, self.off_waste) = (0, 0);
        self.summarise();
    }

    /// `(level, o)` of the point at local index `at` (a summary's entry).
    fn level_of(&self, at: Local) -> Min {
        let o = usize::from(at);
        (self.level(o), o)
    }

    /// `(level + waste, o)` of the point at local index `at`.
    fn unc_of(&self, at: Local) -> Min {
        let o = usize::from(at);
        (self.level(o) + self.waste(o), o)
    }

    /// `(lowest level, first local index)`.
    fn min_level(&self) -> Min {
        self.level_of(self.suffix[0])
    }

    /// `(lowest level + waste, first local index)`.
    fn min_unc(&self) -> Min {
        self.unc_of(self.unc_suffix[0])
    }
}

/// What happens to the points after a rewritten span, walked in order: `level`
/// and `waste` at each point as they were, to what they are now.
enum Tail {
    /// The new levels are lower by `deficit` less the charge the old trajectory
    /// lost to the cap since the span's end (`waste_at_end`); the loss grows by
    /// `du` (the change of the uncapped trajectory) plus what is still owed.
    Deficit {
        deficit: i128,
        waste_at_end: i128,
        du: i128,
    },
    /// The new levels are higher: integrated point by point from the last one
    /// (its time, rate, new level and waste) until they meet the old.
    Surplus { last: (i64, i64, i128, i128) },
    /// The levels are the old ones; the loss differs by `du`.
    Same { du: i128 },
}

impl Tail {
    /// The tail from a point whose new values are `(level, waste)` and old
    /// `(old_level, old_waste)`; `at` is its time and `rate` its rate.
    fn new(
        at: i64,
        rate: i64,
        (level, waste): (i128, i128),
        (old_level, old_waste): (i128, i128),
    ) -> Self {
        let du = level + waste - old_level - old_waste;
        match (old_level - level).signum() {
            0 => Self::Same { du },
            1 => Self::Deficit {
                deficit: old_level - level,
                waste_at_end: old_waste,
                du,
            },
            _ => Self::Surplus {
                last: (at, rate, level, waste),
            },
        }
    }

    /// The new values of the point at time `t` with rate `r` (the segment from
    /// it) and old values `(level, waste)`; moves the walk on.
    fn map(&mut self, t: i64, r: i64, (level, waste): (i128, i128), cap: i128) -> (i128, i128) {
        match *self {
            Self::Same { du } => (level, waste + du),
            Self::Deficit {
                deficit,
                waste_at_end,
                du,
            } => {
                let owed = (deficit - (waste - waste_at_end)).max(0);
                if owed == 0 {
                    *self = Self::Same { du };
                }
                (level - owed, waste + du + owed)
            }
            Self::Surplus {
                last: (t0, r0, l0, w0),
            } => {
                let next = advance(l0, r0, t - t0, cap);
                let w = w0 + l0 + i128::from(r0) * i128::from(t - t0) - next;
                if next == level {
                    *self = Self::Same { du: w - waste };
                } else {
                    *self = Self::Surplus {
                        last: (t, r, next, w),
                    };
                }
                (next, w)
            }
        }
    }

    /// The deficit still owed at a point whose old waste is `waste` (`None`
    /// unless this is a deficit): when it is the same at both ends of a chunk,
    /// it is the same throughout (the waste never falls), and the chunk shifts.
    fn owed(&self, waste: i128) -> Option<i128> {
        match *self {
            Self::Deficit {
                deficit,
                waste_at_end,
                ..
            } => Some((deficit - (waste - waste_at_end)).max(0)),
            Self::Same { .. } | Self::Surplus { .. } => None,
        }
    }
}

/// The points `(time, rate, level, waste)` of a capped integrator, from the
/// domain start to its end (the last point, with rate 0), in chunks.
#[derive(Clone, Debug)]
pub(super) struct Points {
    chunks: Vec<Chunk>,
    /// Global index of each chunk's first point.
    starts: Vec<usize>,
    /// Every point's time, and the chunk holding it: flat, so that a search
    /// by time and finding a point's chunk touch one array each (kept by
    /// splicing, a move of the later entries, on every update).
    times: Vec<i64>,
    chunk_of: Vec<u32>,
    /// Each chunk's last waste (searched without touching the chunks).
    last_wastes: Vec<i128>,
    len: usize,
    /// `(min level over chunks[..=c], global first index)`.
    pre: Vec<Min>,
    /// `(min level over chunks[c..], global first index)`.
    suf: Vec<Min>,
    /// The chunks' minima of the uncapped trajectory (leaf `c`: chunk `c`).
    unc: MinTree,
    /// Storage [`Self::update`] reuses (empty between updates).
    scratch: Scratch,
}

/// The buffers of an update, kept so that a placement allocates nothing.
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// The points integrated afresh.
    new: Flat,
    /// The rewritten group's times and chunk numbers, before they are spliced
    /// into the flat arrays.
    times: Vec<i64>,
    chunk_of: Vec<u32>,
}

impl Points {
    /// Integrates `rate` from `initial`, capped at `cap`.
    pub(super) fn new(rate: &StepFn, initial: i128, cap: i128) -> Self {
        debug_assert!(
            initial <= cap,
            "levels start above the cap: {initial} > {cap}"
        );
        let mut flat = Flat::default();
        let (level, waste) = flat.integrate(rate, rate.start(), rate.end(), initial, 0, cap);
        flat.push(rate.end(), 0, level, waste);
        let mut out = Self {
            chunks: Vec::new(),
            starts: Vec::new(),
            times: Vec::new(),
            chunk_of: Vec::new(),
            last_wastes: Vec::new(),
            len: 0,
            pre: Vec::new(),
            suf: Vec::new(),
            unc: MinTree::default(),
            scratch: Scratch::default(),
        };
        out.times = flat.times.clone();
        out.chunks = flat.into_chunks();
        for (c, ch) in out.chunks.iter().enumerate() {
            out.chunk_of.extend(std::iter::repeat_n(c as u32, ch.len()));
        }
        out.index();
        out
    }

    /// The points, updated in place to `rate`, a rate that equals theirs outside
    /// `[from, to)`: the points from the last one before `from` up to the first
    /// one after `to` are integrated again; from that one on, the points follow
    /// the [`Tail`], chunk by chunk: shifted whole where they can be, rewritten
    /// point by point where the cap changes the shift or a surplus is walked.
    pub(super) fn update(&mut self, rate: &StepFn, cap: i128, from: i64, to: i64) {
        let n = self.len - 1;
        if n == 0 {
            *self = Self::new(rate, self.level(0), cap);
            return;
        }
        // Points [0, k] keep their values; (k, q) are replaced; q on follow the tail.
        let k = self.time_pp(|t| t < from).min(n).saturating_sub(1);
        let q = self.time_pp(|t| t <= to).max(k + 1);
        let (c0, _) = self.locate(k);
        let (c1, _) = self.locate(q - 1);
        let g0 = self.starts[c0];
        let group_old: usize = self.chunks[c0..=c1].iter().map(Chunk::len).sum();
        // Point q as it was (read before the group is taken apart).
        let old_q = (q < self.len).then(|| self.point(q));
        let mut flat = if c0 == c1 {
            self.chunks[c0].take()
        } else {
            let mut flat = Flat::default();
            for c in &mut self.chunks[c0..=c1] {
                flat.append(c.take());
            }
            flat
        };
        let (kl, ql) = (k - g0, q - g0);
        // The group's points from q on (the first of the tail, if q is in it).
        let in_group_tail = flat.times.len() - ql;
        let mut new = std::mem::take(&mut self.scratch.new);
        let until = old_q.map_or(rate.end(), |p| p.0);
        let (level, waste) = new.integrate(
            rate,
            flat.times[kl],
            until,
            flat.levels[kl],
            flat.wastes[kl],
            cap,
        );
        let mut tail = None;
        match old_q {
            None => new.push(rate.end(), 0, level, waste),
            Some((t, r, l, w)) => tail = Some(Tail::new(t, r, (level, waste), (l, w))),
        }
        flat.splice(kl, ql, &mut new);
        self.scratch.new = new;
        let after = c1 + 1;
        if let Some(tail) = tail.as_mut() {
            for i in flat.times.len() - in_group_tail..flat.times.len() {
                let old = (flat.levels[i], flat.wastes[i]);
                (flat.levels[i], flat.wastes[i]) = tail.map(flat.times[i], flat.rates[i], old, cap);
            }
            for c in &mut self.chunks[after..] {
                if let Tail::Same { du } = *tail {
                    if du == 0 {
                        break;
                    }
                    c.off_waste += du;
                    continue;
                }
                let last = c.len() - 1;
                match (tail.owed(c.waste(0)), tail.owed(c.waste(last)), &*tail) {
                    (Some(a), Some(b), &Tail::Deficit { du, .. }) if a == b => {
                        c.off_level -= a;
                        c.off_waste += du + a;
                        if a == 0 {
                            *tail = Tail::Same { du };
                        }
                    }
                    _ => {
                        for o in 0..c.len() {
                            let old = (c.level(o), c.waste(o));
                            let (l, w) = tail.map(c.times[o], c.rates[o], old, cap);
                            c.set(o, l, w);
                        }
                        c.summarise();
                    }
                }
            }
        }
        let m_old = after - c0;
        let m_new = if c0 == c1 && flat.times.len() < 2 * CHUNK {
            self.chunks[c0].refill(flat);
            1
        } else {
            let rebuilt = flat.into_chunks();
            let m = rebuilt.len();
            self.chunks.splice(c0..after, rebuilt);
            m
        };
        // The flat arrays: the group's entries replaced, the later chunks'
        // numbers moved by the change in the number of chunks.
        // (Gathered first: a splice moves the entries after it once when it
        // knows how many come in.)
        let group = &self.chunks[c0..c0 + m_new];
        let group_end = g0 + group_old;
        let Scratch {
            times, chunk_of, ..
        } = &mut self.scratch;
        for (j, c) in group.iter().enumerate() {
            times.extend_from_slice(&c.times);
            chunk_of.extend(std::iter::repeat_n((c0 + j) as u32, c.len()));
        }
        self.times.splice(g0..group_end, times.drain(..));
        self.chunk_of.splice(g0..group_end, chunk_of.drain(..));
        if m_new != m_old {
            let from = g0 + group.iter().map(Chunk::len).sum::<usize>();
            for c in &mut self.chunk_of[from..] {
                *c = (*c as usize + m_new - m_old) as u32;
            }
        }
        self.index();
    }

    /// Recomputes the chunk starts and the minima over chunks.
    fn index(&mut self) {
        self.starts.clear();
        self.last_wastes.clear();
        let mut at = 0;
        for c in &self.chunks {
            self.starts.push(at);
            self.last_wastes.push(c.waste(c.len() - 1));
            at += c.len();
        }
        self.len = at;
        self.pre.clear();
        let mut best = (i128::MAX, 0);
        for (c, g) in self.chunks.iter().zip(&self.starts) {
            let (v, o) = c.min_level();
            if v < best.0 {
                best = (v, g + o);
            }
            self.pre.push(best);
        }
        self.suf.clear();
        self.suf.resize(self.chunks.len(), (i128::MAX, 0));
        let mut best = (i128::MAX, 0);
        for c in (0..self.chunks.len()).rev() {
            let (v, o) = self.chunks[c].min_level();
            if v <= best.0 {
                best = (v, self.starts[c] + o);
            }
            self.suf[c] = best;
        }
        self.unc.rebuild(self.chunks.iter().map(|c| c.min_unc().0));
    }

    /// Debug builds: the flat arrays agree with the chunks.
    #[cfg(debug_assertions)]
    pub(super) fn check_flat(&self) {
        let mut i = 0;
        for (c, ch) in self.chunks.iter().enumerate() {
            debug_assert!(
                !ch.times.is_empty() && ch.len() < 2 * CHUNK,
                "chunk {c} of {} points",
                ch.len()
            );
            for o in 0..ch.len() {
                debug_assert_eq!(
                    (self.times[i], self.chunk_of[i] as usize),
                    (ch.times[o], c),
                    "point {i}"
                );
                i += 1;
            }
        }
        debug_assert_eq!(
            (i, self.times.len(), self.chunk_of.len()),
            (self.len, self.len, self.len)
        );
    }

    /// The number of points (segments + 1).
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// `(chunk, offset)` of point `i`.
    fn locate(&self, i: usize) -> (usize, usize) {
        let c = self.chunk_of[i] as usize;
        (c, i - self.starts[c])
    }

    /// Point `i`'s time.
    pub(super) fn time(&self, i: usize) -> i64 {
        self.times[i]
    }

    /// Point `i`'s level.
    pub(super) fn level(&self, i: usize) -> i128 {
        let (c, o) = self.locate(i);
        self.chunks[c].level(o)
    }

    /// The charge lost to the cap before point `i`.
    pub(super) fn waste(&self, i: usize) -> i128 {
        let (c, o) = self.locate(i);
        self.chunks[c].waste(o)
    }

    /// The first point's time (the domain start).
    pub(super) fn first_time(&self) -> i64 {
        self.times[0]
    }

    /// The last point's time (the domain end).
    pub(super) fn last_time(&self) -> i64 {
        self.times[self.len - 1]
    }

    /// The last point at or before `t` among points `[0, n)` (`0` when `t` is
    /// before them all), with its values: the segment holding `t`.
    pub(super) fn segment_at(&self, t: i64) -> (usize, (i64, i64, i128, i128)) {
        let n = self.len - 1;
        let i = self.times[..n]
            .partition_point(|&x| x <= t)
            .saturating_sub(1);
        (i, self.point(i))
    }

    /// The points from `i` on, in order.
    pub(super) fn iter_from(&self, i: usize) -> impl Iterator<Item = (i64, i64, i128, i128)> + '_ {
        let (c, o) = if i < self.len {
            self.locate(i)
        } else {
            (self.chunks.len(), 0)
        };
        self.chunks[c.min(self.chunks.len())..]
            .iter()
            .enumerate()
            .flat_map(move |(j, ch)| {
                let from = if j == 0 { o } else { 0 };
                (from..ch.len()).map(move |o| (ch.times[o], ch.rates[o], ch.level(o), ch.waste(o)))
            })
    }

    /// `(time, rate, level, waste)` of point `i`.
    pub(super) fn point(&self, i: usize) -> (i64, i64, i128, i128) {
        let (c, o) = self.locate(i);
        let ch = &self.chunks[c];
        (ch.times[o], ch.rates[o], ch.level(o), ch.waste(o))
    }

    /// Every point in order.
    pub(super) fn iter(&self) -> impl Iterator<Item = (i64, i64, i128, i128)> + '_ {
        self.chunks.iter().flat_map(|c| {
            (0..c.len()).map(move |o| (c.times[o], c.rates[o], c.level(o), c.waste(o)))
        })
    }

    /// `(min of the levels of points [0, i], first index)`.
    pub(super) fn prefix_min(&self, i: usize) -> Min {
        let (c, o) = self.locate(i);
        let ch = &self.chunks[c];
        let (v, at) = ch.level_of(ch.prefix[o]);
        let here = (v, self.starts[c] + at);
        match c.checked_sub(1).map(|b| self.pre[b]) {
            Some(before) if before.0 <= here.0 => before,
            _ => here,
        }
    }

    /// `(min of the levels of points [i, len), first index)`.
    pub(super) fn suffix_min(&self, i: usize) -> Min {
        let (c, o) = self.locate(i);
        let ch = &self.chunks[c];
        let (v, at) = ch.level_of(ch.suffix[o]);
        let here = (v, self.starts[c] + at);
        match self.suf.get(c + 1) {
            Some(&after) if after.0 < here.0 => after,
            _ => here,
        }
    }

    /// `(min of level + waste over points [l, r), first index)`, `None` when empty.
    pub(super) fn unc_min(&self, l: usize, r: usize) -> Option<Min> {
        let r = r.min(self.len);
        if l >= r {
            return None;
        }
        let (cl, ol) = self.locate(l);
        let (cr, or) = self.locate(r - 1);
        let mut best: Option<Min> = None;
        let mut take = |x: Min| {
            if best.is_none_or(|b| x.0 < b.0) {
                best = Some(x);
            }
        };
        if cl == cr {
            let ch = &self.chunks[cl];
            for o in ol..=or {
                take((ch.level(o) + ch.waste(o), self.starts[cl] + o));
            }
            return best;
        }
        let left = &self.chunks[cl];
        let (v, at) = left.unc_of(left.unc_suffix[ol]);
        take((v, self.starts[cl] + at));
        if let Some((v, c)) = self.unc.query(cl + 1, cr) {
            take((v, self.starts[c] + self.chunks[c].min_unc().1));
        }
        let right = &self.chunks[cr];
        let (v, at) = right.unc_of(right.unc_prefix[or]);
        take((v, self.starts[cr] + at));
        best
    }

    /// The first point whose time fails `pred` (`pred` holds on a prefix).
    pub(super) fn time_pp(&self, pred: impl Fn(i64) -> bool) -> usize {
        self.times.partition_point(|&t| pred(t))
    }

    /// [`Self::time_pp`], searched forward from point `i` when `pred` holds
    /// there (galloping: a boundary near `i`, such as the end of a short span
    /// that starts there, is found reading a few nearby entries); else the
    /// plain search.
    pub(super) fn time_pp_from(&self, i: usize, pred: impl Fn(i64) -> bool) -> usize {
        if self.times.get(i).is_none_or(|&t| !pred(t)) {
            return self.time_pp(pred);
        }
        // pred(times[i]) holds: find the end of the prefix past `i`.
        let mut lo = i + 1;
        let mut step = 1;
        while lo + step <= self.times.len() && pred(self.times[lo + step - 1]) {
            lo += step;
            step *= 2;
        }
        let hi = (lo + step).min(self.times.len());
        lo + self.times[lo..hi].partition_point(|&t| pred(t))
    }

    /// The first point whose waste fails `pred` (`pred` holds on a prefix: the
    /// waste never falls).
    pub(super) fn waste_pp(&self, pred: impl Fn(i128) -> bool) -> usize {
        let c = self.last_wastes.partition_point(|&w| pred(w));
        match self.chunks.get(c) {
            None => self.len,
            Some(ch) => self.starts[c] + ch.wastes.partition_point(|&w| pred(w + ch.off_waste)),
        }
    }

    /// The first point whose prefix minimum fails `pred` (`pred` holds on a
    /// prefix: it must hold for every larger value).
    pub(super) fn prefix_min_pp(&self, pred: impl Fn(i128) -> bool) -> usize {
        let c = self.pre.partition_point(|m| pred(m.0));
        match self.chunks.get(c) {
            None => self.len,
            Some(ch) => self.starts[c] + ch.prefix.partition_point(|&at| pred(ch.level_of(at).0)),
        }
    }

    /// The first point whose suffix minimum satisfies `ok` (`ok` holds for every
    /// value above one it holds for; suffix minima never fall).
    pub(super) fn suffix_min_first(&self, ok: impl Fn(i128) -> bool) -> usize {
        let c = self.suf.partition_point(|m| !ok(m.0));
        if c == 0 {
            return 0;
        }
        let ch = &self.chunks[c - 1];
        self.starts[c - 1] + ch.suffix.partition_point(|&at| !ok(ch.level_of(at).0))
    }

    /// The times of the points in `[lo, hi]`.
    pub(super) fn times_in(&self, lo: i64, hi: i64) -> Vec<i64> {
        let (a, b) = (self.time_pp(|t| t < lo), self.time_pp(|t| t <= hi));
        self.times[a..b.max(a)].to_vec()
    }
}

/// Points in flat vectors, while a span is rewritten.
#[derive(Clone, Debug, Default)]
struct Flat {
    times: Vec<i64>,
    rates: Vec<i64>,
    levels: Vec<i128>,
    wastes: Vec<i128>,
}

impl Flat {
    /// Moves `other`'s points to the end.
    fn append(&mut self, mut other: Flat) {
        self.times.append(&mut other.times);
        self.rates.append(&mut other.rates);
        self.levels.append(&mut other.levels);
        self.wastes.append(&mut other.wastes);
    }

    /// Appends one point.
    fn push(&mut self, t: i64, r: i64, level: i128, waste: i128) {
        self.times.push(t);
        self.rates.push(r);
        self.levels.push(level);
        self.wastes.push(waste);
    }

    /// Pushes the segments of `rate` on `[from, until)` integrated from `level`
    /// and `waste`; returns the level and waste at `until`.
    fn integrate(
        &mut self,
        rate: &StepFn,
        from: i64,
        until: i64,
        mut level: i128,
        mut waste: i128,
        cap: i128,
    ) -> (i128, i128) {
        for (lo, hi, r) in rate.segments(from, until) {
            self.push(lo, r, level, waste);
            let next = advance(level, r, hi - lo, cap);
            waste += level + i128::from(r) * i128::from(hi - lo) - next;
            level = next;
        }
        (level, waste)
    }

    /// Replaces points `[a, b)` with `new`'s, leaving `new` empty.
    fn splice(&mut self, a: usize, b: usize, new: &mut Flat) {
        self.times.splice(a..b, new.times.drain(..));
        self.rates.splice(a..b, new.rates.drain(..));
        self.levels.splice(a..b, new.levels.drain(..));
        self.wastes.splice(a..b, new.wastes.drain(..));
    }

    /// Cut into chunks of `CHUNK..2 * CHUNK` points (one smaller chunk only when
    /// there are fewer points than that).
    fn into_chunks(self) -> Vec<Chunk> {
        let n = self.times.len();
        let m = (n / CHUNK).max(1);
        let mut out = Vec::with_capacity(m);
        let (mut times, mut rates, mut levels, mut wastes) =
            (self.times, self.rates, self.levels, self.wastes);
        // Split from the back so each split is a move of the tail.
        let mut ends: Vec<usize> = (1..m).map(|j| j * n / m).collect();
        ends.reverse();
        for at in ends {
            out.push(Chunk::new(
                times.split_off(at),
                rates.split_off(at),
                levels.split_off(at),
                wastes.split_off(at),
            ));
        }
        out.push(Chunk::new(times, rates, levels, wastes));
        out.reverse();
        out
    }
}

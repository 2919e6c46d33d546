//! The search's numeric building blocks: cells between critical points, and the
//! feasible part of a concave function on a cell (whole, or its point nearest
//! a preferred one).

use crate::timeline::{Interval, IntervalSet};

/// Splits `set` at every point of `points` that falls strictly inside one of its
/// intervals: the cells `[a, b]` between consecutive critical points.
pub(super) fn cells(set: &IntervalSet, mut points: Vec<i64>) -> Vec<(i64, i64)> {
    // The points come as a few sorted runs (breakpoints shifted by each offset):
    // the stable sort merges runs in O(n log runs).
    points.sort();
    points.dedup();
    let mut out = Vec::new();
    for iv in set.intervals() {
        let mut a = iv.lo;
        let from = points.partition_point(|&p| p <= iv.lo);
        for &p in &points[from..] {
            if p > iv.hi {
                break;
            }
            out.push((a, p - 1));
            a = p;
        }
        out.push((a, iv.hi));
    }
    out
}

/// For a concave integer function `g` on `[a, b]`: the interval where `g >= 0`
/// (if any), and the start of the highest value (a probe for reporting).
pub(super) fn concave_feasible(a: i64, b: i64, g: &dyn Fn(i64) -> i128) -> (Option<Interval>, i64) {
    let (ga, gb) = (g(a), g(b));
    if ga >= 0 && gb >= 0 {
        return (Some(Interval::new(a, b)), a);
    }
    if ga >= 0 {
        return (Some(Interval::new(a, last_ok(a, b - 1, g))), a);
    }
    if gb >= 0 {
        return (Some(Interval::new(first_ok(a + 1, b, g), b)), b);
    }
    // Both ends fail. If g does not rise right after a (or does not fall right
    // before b), concavity puts the maximum at that end: nothing passes.
    if a == b || g(a + 1) <= ga {
        return (None, a);
    }
    if g(b - 1) <= gb {
        return (None, b);
    }
    // Otherwise find the maximum.
    let l = peak(a, b, g);
    if g(l) < 0 {
        return (None, l);
    }
    (
        Some(Interval::new(first_ok(a + 1, l, g), last_ok(l, b - 1, g))),
        l,
    )
}

/// For a concave integer function `g` on `[a, b]` and `p` in it, with
/// `gp = g(p)`: the `x` with `g(x) >= 0` nearest `p` (`None` when there is
/// none). The feasible set is an interval: `p` itself when it passes; else
/// the interval lies on the one side where `g` rises from `p`, and the answer
/// is its near end, found past that side's maximum. `p` as the maximum (`g`
/// rising on neither side) fails, and so does everything.
pub(super) fn concave_nearest(
    a: i64,
    b: i64,
    p: i64,
    gp: i128,
    g: &dyn Fn(i64) -> i128,
) -> Option<i64> {
    if gp >= 0 {
        return Some(p);
    }
    if p < b && g(p + 1) > gp {
        // The tangents at both ends of the rising side bound its maximum: when
        // they prove it negative, the peak need not be searched for.
        if b - p >= TANGENT_MIN_WIDTH && tangent_bound(p, b, gp, g(p + 1), g(b - 1), g(b)) < 0 {
            return None;
        }
        let top = peak(p + 1, b, g);
        (g(top) >= 0).then(|| first_ok(p + 1, top, g))
    } else if p > a && g(p - 1) > gp {
        if p - a >= TANGENT_MIN_WIDTH && tangent_bound(a, p, g(a), g(a + 1), g(p - 1), gp) < 0 {
            return None;
        }
        let top = peak(a, p - 1, g);
        (g(top) >= 0).then(|| last_ok(top, p - 1, g))
    } else {
        None
    }
}

/// [`concave_nearest`] bounds a side of at least this many seconds by its
/// tangents ([`tangent_bound`]) before searching its peak: on a shorter one
/// the search costs about as much.
const TANGENT_MIN_WIDTH: i64 = 8;

/// An upper bound on the maximum over the integers of `[l, r]` (`l < r`) of a
/// concave integer function `g`, from `gl = g(l)`, `gl1 = g(l + 1)`,
/// `gr1 = g(r - 1)` and `gr = g(r)`. A concave function's differences never
/// rise, so `g(x) <= gl + (x - l) * (gl1 - gl)` and `g(x) <= gr + (r - x) *
/// (gr1 - gr)` on the whole of `[l, r]`: the maximum lies below the lower of
/// the two lines, highest at an integer next to where they cross. Exact
/// integer arithmetic; `i128::MAX` (no bound) should it overflow.
pub(super) fn tangent_bound(l: i64, r: i64, gl: i128, gl1: i128, gr1: i128, gr: i128) -> i128 {
    let rise = gl1 - gl;
    let fall = gr1 - gr;
    if rise <= 0 {
        // Falling from `l` on: the maximum is `g(l)`.
        return gl;
    }
    if fall <= 0 {
        // Rising up to `r`: the maximum is `g(r)`.
        return gr;
    }
    let (l, r) = (i128::from(l), i128::from(r));
    let below = |x: i128| -> Option<i128> {
        let left = gl.checked_add(x.checked_sub(l)?.checked_mul(rise)?)?;
        let right = gr.checked_add(r.checked_sub(x)?.checked_mul(fall)?)?;
        Some(left.min(right))
    };
    // The lines cross at `x = (gr - gl + r * fall + l * rise) / (rise + fall)`.
    let cross = || -> Option<i128> {
        let num = gr
            .checked_sub(gl)?
            .checked_add(r.checked_mul(fall)?)?
            .checked_add(l.checked_mul(rise)?)?;
        Some(num.div_euclid(rise.checked_add(fall)?))
    };
    let Some(x) = cross() else {
        return i128::MAX;
    };
    [x, x + 1]
        .into_iter()
        .map(|x| below(x.clamp(l, r)))
        .try_fold(i128::MIN, |best, v| v.map(|v| best.max(v)))
        .unwrap_or(i128::MAX)
}

/// The largest `x` in `[from, to]` with `g(x) >= 0`, given `g(from) >= 0`
/// and the passing set an interval.
fn last_ok(from: i64, to: i64, g: &dyn Fn(i64) -> i128) -> i64 {
    nearest_ok(to + 1, from, g)
}

/// The smallest `x` in `[from, to]` with `g(x) >= 0`, given `g(to) >= 0` and
/// the passing set an interval.
fn first_ok(from: i64, to: i64, g: &dyn Fn(i64) -> i128) -> i64 {
    nearest_ok(from - 1, to, g)
}

/// The passing `x` nearest `bad` between `bad` (taken to fail) and `ok`
/// (which passes), either way round, bisecting: the passing starts in
/// between are the ones on `ok`'s side of one boundary.
fn nearest_ok(mut bad: i64, mut ok: i64, g: &dyn Fn(i64) -> i128) -> i64 {
    while bad.abs_diff(ok) > 1 {
        let mid = bad.min(ok) + (bad.max(ok) - bad.min(ok)) / 2;
        if g(mid) >= 0 {
            ok = mid;
        } else {
            bad = mid;
        }
    }
    ok
}

/// The first `s` in `[l, r]` with `g(s + 1) <= g(s)` (`r` when none), for
/// `g` concave on `[l, r + 1]`: where it stops rising, its maximum.
fn peak(mut l: i64, mut r: i64, g: &dyn Fn(i64) -> i128) -> i64 {
    while l < r {
        let mid = l + (r - l) / 2;
        if g(mid + 1) > g(mid) {
            l = mid + 1;
        } else {
            r = mid;
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concave_search_finds_exact_boundaries() {
        // Tent function peaking at 40: feasible where g >= 0.
        for (peak, width) in [(40i64, 5i64), (40, 0), (0, 3), (100, 200), (40, -1)] {
            let g = move |s: i64| i128::from(width - (s - peak).abs());
            let (iv, _) = concave_feasible(0, 100, &g);
            let brute: Vec<i64> = (0..=100).filter(|&s| g(s) >= 0).collect();
            match iv {
                None => assert!(brute.is_empty(), "{peak} {width}"),
                Some(iv) => {
                    assert_eq!(
                        (iv.lo, iv.hi),
                        (brute[0], *brute.last().unwrap()),
                        "{peak} {width}"
                    )
                }
            }
        }
        // Plateau at the maximum.
        let g = |s: i64| i128::from((s.min(60) - s.max(30)).min(0) + 1 - i64::from(s > 90) * 100);
        let (iv, _) = concave_feasible(0, 100, &g);
        assert!(iv.is_some());
    }

    /// The nearest passing point is the brute-force nearest (the earlier on a
    /// tie cannot arise: the passing set is one interval, and `p` is outside
    /// it or the answer), for tents, plateaus and lines, from every `p`.
    #[test]
    fn concave_nearest_is_the_nearest_passing_point() {
        let tent = |peak: i64, width: i64| move |s: i64| i128::from(width - (s - peak).abs());
        let mut shapes: Vec<Box<dyn Fn(i64) -> i128>> = Vec::new();
        for (peak, width) in [
            (40i64, 5i64),
            (40, 0),
            (0, 3),
            (20, 200),
            (40, -1),
            (100, 7),
        ] {
            shapes.push(Box::new(tent(peak, width)));
        }
        shapes.push(Box::new(|s: i64| {
            i128::from((s.min(60) - s.max(30)).min(0) + 1)
        }));
        shapes.push(Box::new(|s: i64| {
            i128::from((s.min(60) - s.max(30)).min(0) - 1)
        }));
        shapes.push(Box::new(|s: i64| i128::from(50 - s)));
        shapes.push(Box::new(|s: i64| i128::from(s - 70)));
        for g in &shapes {
            let (a, b) = (10, 100);
            for p in a..=b {
                let brute = (a..=b)
                    .filter(|&x| g(x) >= 0)
                    .min_by_key(|&x| ((x - p).abs(), x));
                assert_eq!(
                    concave_nearest(a, b, p, g(p), g.as_ref()),
                    brute,
                    "from {p}"
                );
            }
        }
    }

    /// The tangent bound is at least the maximum, for tents, plateaus, lines
    /// and parabolas on every subrange, and the maximum itself on a tent whose
    /// peak the tangents meet at.
    #[test]
    fn tangent_bound_bounds_the_maximum() {
        let mut shapes: Vec<Box<dyn Fn(i64) -> i128>> = Vec::new();
        for (peak, width) in [(40i64, 5i64), (40, -30), (0, 3), (100, -7), (63, -2)] {
            shapes.push(Box::new(move |s: i64| i128::from(width - (s - peak).abs())));
        }
        shapes.push(Box::new(|s: i64| {
            i128::from((s.min(60) - s.max(30)).min(0) - 1)
        }));
        shapes.push(Box::new(|s: i64| i128::from(50 - 3 * s)));
        shapes.push(Box::new(|s: i64| i128::from(2 * s - 70)));
        shapes.push(Box::new(|s: i64| -i128::from((s - 47) * (s - 47)) - 5));
        for g in &shapes {
            for l in (0..100).step_by(7) {
                for r in (l + 1)..=100 {
                    let max = (l..=r).map(g.as_ref()).max().unwrap();
                    let bound = tangent_bound(l, r, g(l), g(l + 1), g(r - 1), g(r));
                    assert!(bound >= max, "[{l}, {r}]: {bound} < {max}");
                }
            }
        }
        let tent = |s: i64| i128::from(-3 - (s - 40).abs());
        assert_eq!(
            tangent_bound(0, 100, tent(0), tent(1), tent(99), tent(100)),
            -3
        );
        assert_eq!(tangent_bound(0, 10, -5, -4, -2, -3), 1);
    }

    #[test]
    fn cells_split_at_points() {
        let set: IntervalSet = [Interval::new(0, 10), Interval::new(20, 30)]
            .into_iter()
            .collect();
        assert_eq!(
            cells(&set, vec![5, 0, 21, 40, 10]),
            vec![(0, 4), (5, 9), (10, 10), (20, 20), (21, 30)]
        );
    }
}

"""The largest stable step by bisection, shared by the Yade scripts.

Plain Python (no Yade import): the scripts pass their own trial, which restores
the frozen scene, perturbs it, runs it at a step and says whether it grew.
Tested without Yade by `test_stability_search.py`.
"""
import sys


def grows(advance, kinetic, nmax, growth):
    """Run `advance(chunk)` until `nmax` steps or until the kinetic energy
    reaches `growth` times its start (NaN counts as growth).

    Short chunks first: a clearly unstable step overflows within about 100
    steps, and Yade's collider does not survive non-finite positions.
    Returns (unstable, steps, largest kinetic energy / start)."""
    e0 = kinetic()
    emax = e0
    steps = 0
    grew = False
    while steps < nmax and not grew:
        chunk = 5 if steps < 200 else (20 if steps < 1000 else 100)
        advance(chunk)
        steps += chunk
        e = kinetic()
        grew = not (e < growth * e0)      # NaN grows: max() would drop it
        emax = e if grew else max(emax, e)
    return grew, steps, emax / e0


def report(trials, dt, unstable, steps, ratio):
    """Record one trial and print its line."""
    trials.append({'dt': dt, 'unstable': unstable, 'steps': steps, 'ke_ratio_max': ratio})
    print('  dt=%.8e  %s  steps=%d  max KE/KE0=%.3e' % (dt, 'UNSTABLE' if unstable else 'stable', steps, ratio))
    sys.stdout.flush()


def bisect(trial, dt, widen, rtol, max_trials=200):
    """Bracket the largest stable step from `dt`, widening by the factor
    `widen`, then halve the bracket until (hi - lo)/lo <= rtol.

    `trial(dt)` is True when dt is unstable. Returns (lo, hi): lo stable,
    hi unstable."""
    lo, hi = None, None
    n = 0
    while lo is None or hi is None:
        if n >= max_trials:
            raise RuntimeError('no bracket within %d trials' % max_trials)
        n += 1
        if trial(dt):
            hi = dt
            dt = dt / widen
        else:
            lo = dt
            dt = dt * widen
    while (hi - lo) / lo > rtol:
        mid = 0.5 * (lo + hi)
        if trial(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


def confirm(long_trial, lo, hi, rtol, max_trials=200):
    """Re-run the stable end `lo` with `long_trial` (a run several times
    longer); step down by rtol while it fails, at most max_trials times.

    `long_trial(dt)` returns (unstable, steps). Returns (lo, hi, records)."""
    records = []
    while True:
        if len(records) >= max_trials:
            raise RuntimeError('no stable long run within %d trials' % max_trials)
        unstable, steps = long_trial(lo)
        records.append({'dt': lo, 'steps': steps, 'unstable': unstable})
        if not unstable:
            return lo, hi, records
        hi = lo
        lo = lo * (1 - rtol)

"""Checks of stability_search.py without Yade: python3 test_stability_search.py"""
import math
import stability_search as search

LIMIT = 1.2345e-4


def test_bisect_brackets_the_limit():
    for start in (1e-5, LIMIT, 5e-4):
        for widen in (1.03, 1.1):
            calls = []
            lo, hi = search.bisect(lambda d: calls.append(d) or d > LIMIT, start, widen, 1e-4)
            assert lo <= LIMIT < hi and (hi - lo) / lo <= 1e-4, (start, widen, lo, hi)


def test_bisect_gives_up():
    try:
        search.bisect(lambda d: True, 1.0, 1.05, 1e-3, max_trials=10)
    except RuntimeError:
        return
    raise AssertionError('no bracket was not refused')


def test_grows_on_a_growing_and_a_decaying_system():
    for q, expect in ((1.01, True), (0.999, False), (float('nan'), True)):
        state = {'e': 1.0}
        def advance(n):
            state['e'] *= q ** n
        unstable, steps, ratio = search.grows(advance, lambda: state['e'], 4000, 1e3)
        assert unstable == expect, (q, unstable)
        if q == 1.01:   # 1.01^n reaches 1e3 at n = 695: the first check past it
            assert 695 <= steps <= 720 and ratio >= 1e3, (steps, ratio)
        if q == 0.999:
            assert steps == 4000 and ratio == 1.0


def test_confirm_steps_down_until_the_long_run_holds():
    lo, hi, rec = search.confirm(lambda d: (d > 0.99 * LIMIT, 100), LIMIT, 1.0001 * LIMIT, 1e-3)
    assert lo <= 0.99 * LIMIT and hi > 0.99 * LIMIT and rec[-1]['unstable'] is False
    assert len(rec) == math.ceil(math.log(0.99) / math.log(1 - 1e-3)) + 1, len(rec)


if __name__ == '__main__':
    for name, f in list(globals().items()):
        if name.startswith('test_'):
            f()
            print('ok', name)

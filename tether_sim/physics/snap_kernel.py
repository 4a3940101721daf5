"""The compiled per-sample state machine of the slack/snap detector (:mod:`tether_sim.physics.snap`, whose
docstring states the rules; :class:`tether_sim.physics.snap.SnapDetector` drives it and guards its events).

Each monitored location has one row of state (the columns below); the kernel advances every location over a
chunk of samples and writes event rows (slack started, snap, slack restarted) to a table.
"""

import numpy as np

from tether_sim.numerics.jit import jit

# Per-location machine state columns.
(_MODE, _SLACK_START, _MIN_T, _EXIT_T, _RETENSION_T, _PREV_T, _PREV_TENSION, _HAS_PREV, _FRONT_T, _NEXT_RET,
 # a stage of a re-tensioning window: its running maximum (tension, time, slack exit and front at it) and its
 # drop back into slack (time, tension there, least since); the window's own stage, then the next one's, in
 # the same order (_NEXT: the offset between the two; _stage_peak / _stage_drop serve both)
 _PEAK, _PEAK_T, _PEAK_EXIT, _PEAK_FRONT, _DROP_T, _DROP_Y, _DROP_MIN,
 _NEXT_PEAK, _NEXT_PEAK_T, _NEXT_PEAK_EXIT, _NEXT_PEAK_FRONT, _NEXT_DROP_T, _NEXT_DROP_Y, _NEXT_DROP_MIN,
 _PUBLISHED, _RESET_Y, _RESET_T) = range(27)
_N_STATE = 27
_STAGE_SIZE = _NEXT_PEAK - _PEAK  # the columns of one stage
_NEXT = _STAGE_SIZE  # offset of the next stage's columns from the window's
_TIME_COLUMNS = [_SLACK_START, _EXIT_T, _PEAK_T, _RETENSION_T, _PREV_T, _PEAK_EXIT, _DROP_T, _FRONT_T, _PEAK_FRONT,
                 _NEXT_RET, _NEXT_PEAK_T, _NEXT_PEAK_EXIT, _NEXT_PEAK_FRONT, _NEXT_DROP_T, _RESET_T]  # (shift_time)
# _FRONT_T: the last upward crossing of the re-tension level (the start of the front now rising); _PEAK_FRONT
# its value at the running maximum (the guard's rise: SnapGuard.check).
# _DROP_T: within a re-tensioning window, when the tension first fell back below the slack threshold after
# the window's running maximum (NaN while it has not); _DROP_Y the sample there, _DROP_MIN the least since
# (until a next re-tensioning begins).
# _NEXT_*: after that drop, the re-tensioning that rose above the re-tension level again (_NEXT_RET its start,
# NaN while none), with its own running maximum (time, slack exit and front at it) and its own drop: kept
# beside the window's larger earlier peak so that it gets its own window when that one closes (a one-step
# spike early in a slack period must not swallow the smaller real snap that follows it).
# _PUBLISHED: the largest peak of the open re-tensioning window already emitted as a snap (-inf while none): the
# window stays open after it, until the tension falls back into slack or 10 windows after the re-tensioning
# began, and a later peak above it is the same snap's new maximum (an event row of kind 3).
# _RESET_Y: after the window forgot a running maximum as numerical (_forget_spike), the tension it went on from
# (-inf while none): the window's floor; a later maximum counts only above it, and its rise runs from _RESET_T, the
# last upward crossing of that level (the front of what rises after a spike, as _FRONT_T is of a rise from slack).
_TAUT, _SLACK, _RISING = 0.0, 1.0, 2.0
# Event rows: kind (0 slack started, 1 snap, 2 slack restarted where the tension fell back after a closed
# re-tensioning, 3 a new maximum of a snap already emitted: same slack period, larger peak), location, time,
# tension/peak, min, slack_start, exit time, start of the re-tensioning holding the peak, start of the front
# holding the peak (re-tension level); kind 4: a running maximum forgotten as numerical (_forget_spike), with
# the same columns as a snap (the guard turns it into a numerical warning).
_N_EVENT = 9
_SNAP, _NEW_MAXIMUM, _SPIKE = 1.0, 3.0, 4.0


@jit
def _crossing_time(t0, y0, t1, y1, level):
    """Linear interpolation of the time where y crosses ``level`` between two samples."""
    if y1 == y0:
        return t1
    return t0 + (level - y0) * (t1 - t0) / (y1 - y0)


@jit
def _emit(events, n, kind, loc, time, value, min_t, start, exit_t, rise_start, front_start):
    events[n, 0] = kind
    events[n, 1] = loc
    events[n, 2] = time
    events[n, 3] = value
    events[n, 4] = min_t
    events[n, 5] = start
    events[n, 6] = exit_t
    events[n, 7] = rise_start
    events[n, 8] = front_start
    return n + 1


@jit
def _stage_peak(s, o, t, y):
    """A larger maximum (t, y) of the stage at column offset ``o`` (0: the window's, _NEXT: the next one's):
    whatever rose after a drop belongs to it, so its drop is forgotten."""
    s[_PEAK + o] = y
    s[_PEAK_T + o] = t
    s[_PEAK_EXIT + o] = s[_EXIT_T]
    s[_PEAK_FRONT + o] = max(s[_FRONT_T], s[_RESET_T])
    s[_DROP_T + o] = np.nan


@jit
def _stage_drop(s, o, has_prev, t0, y0, t, y, lo):
    """Watch the stage at offset ``o`` for its first fall below the slack level ``lo`` after its maximum."""
    if has_prev and y0 >= lo > y:
        s[_DROP_T + o] = _crossing_time(t0, y0, t, y, lo)
        s[_DROP_Y + o] = y
        s[_DROP_MIN + o] = y


@jit
def _start_next(s, t, y):
    """The re-tensioning rising above the re-tension level at (t, y) after the window's drop."""
    s[_NEXT_RET] = t
    _stage_peak(s, _NEXT, t, y)


@jit
def _slack_elsewhere(st, j):
    """Another location of the cable (a row of ``st`` other than ``j``) is still slack in the slack episode of
    location ``j``'s open window: its slack period began no later than ``j``'s re-tensioning, and it has not been
    taken up since (slack, or re-tensioning with no snap out yet: a weak stage or a peak still within its window)."""
    for k in range(st.shape[0]):
        if k == j or st[k, _SLACK_START] > st[j, _RETENSION_T]:
            continue
        if st[k, _MODE] == _SLACK or (st[k, _MODE] == _RISING and st[k, _PUBLISHED] == -np.inf):
            return True
    return False


@jit
def _forget_spike(s, j, t, y, hi, snap_level, min_duration, events, n_ev):
    """Location ``j``'s running maximum rose from its front (the last upward crossing of the re-tension level, or
    of the level the window went on from after an earlier spike) in less than an element crossing, and nothing
    larger came for a crossing after it, the tension out of slack all along: a rise faster than the
    discretisation can carry a physical front (docs/snap_guard.md, "Each peak judged as it comes"). The window
    forgets it, so that the re-tensioning that follows, smaller or not, is measured on its own: emit it as a spike
    row (kind 4, when it reached the snap level after a slack period of ``min_duration``: what would have been
    judged as a snap) and go on from the current sample ``(t, y)``: still re-tensioning, with ``y`` as the
    window's floor, when it is above the re-tension level ``hi``; else slack, as if the spike had not been.
    Returns the number of event rows."""
    if s[_PEAK] >= snap_level and s[_PEAK_EXIT] - s[_SLACK_START] >= min_duration:
        n_ev = _emit(events, n_ev, _SPIKE, j, s[_PEAK_T], s[_PEAK], s[_MIN_T], s[_SLACK_START], s[_PEAK_EXIT],
                     s[_PEAK_EXIT], s[_PEAK_FRONT])
    if y > hi:
        s[_RESET_Y] = y
        s[_RESET_T] = t
        _stage_peak(s, 0, t, y)
    else:
        s[_MODE] = _SLACK
        s[_PEAK] = -np.inf
        s[_RESET_Y] = -np.inf
        s[_RESET_T] = -np.inf
    return n_ev


@jit
def _close_window(s, j, y, lo, snap_level, min_duration, follow, events, n_ev):
    """Close location ``j``'s re-tensioning window (current sample ``y``): emit its snap event when its peak
    reaches ``snap_level``, is above the peak already emitted from the window and the slack before it lasted
    ``min_duration``, then set what follows (``follow``: a window that reached the snap level and is still out
    of slack stays open for a new maximum). Returns the number of event rows."""
    reached = s[_PEAK] >= snap_level and s[_PEAK] > s[_RESET_Y]  # (not the floor a spike left: _forget_spike)
    if reached and s[_PEAK] > s[_PUBLISHED] and s[_PEAK_EXIT] - s[_SLACK_START] >= min_duration:
        kind = _SNAP if s[_PUBLISHED] == -np.inf else _NEW_MAXIMUM
        n_ev = _emit(events, n_ev, kind, j, s[_PEAK_T], s[_PEAK], s[_MIN_T], s[_SLACK_START], s[_PEAK_EXIT],
                     s[_PEAK_EXIT], s[_PEAK_FRONT])
    if np.isnan(s[_DROP_T]):  # taut since the peak
        if reached and follow:  # the episode goes on: a later, larger peak is this snap's new maximum
            s[_PUBLISHED] = s[_PEAK]
            return n_ev
        s[_MODE] = _TAUT
        return n_ev
    # The tension fell back below the slack level after the peak. A re-tensioning that reached the snap level
    # ended the slack period: a new one began where it fell (row kind 2; SnapDetector.update merges it back
    # into the old one when the guard rejects the re-tensioning). A weaker one is merged into the slack period.
    if reached:
        s[_SLACK_START] = s[_DROP_T]
        s[_MIN_T] = s[_DROP_MIN]
        n_ev = _emit(events, n_ev, 2.0, j, s[_DROP_T], s[_DROP_Y], s[_DROP_Y], s[_DROP_T], s[_DROP_T], s[_DROP_T],
                     s[_DROP_T])
    if not np.isnan(s[_NEXT_RET]):  # what rose again after the drop gets its own window, from its own start
        s[_MODE] = _RISING
        s[_RETENSION_T] = s[_NEXT_RET]
        for k in range(_STAGE_SIZE):  # the next stage becomes the window's
            s[_PEAK + k] = s[_PEAK + _NEXT + k]
        s[_NEXT_RET] = np.nan
        s[_PUBLISHED] = -np.inf
        s[_RESET_Y] = -np.inf
        s[_RESET_T] = -np.inf
    else:  # slack now (or between the slack and re-tension levels: not re-tensioned yet)
        s[_MODE] = _SLACK
        s[_PEAK] = -np.inf
        s[_PUBLISHED] = -np.inf
        if y < lo:
            s[_EXIT_T] = s[_SLACK_START]
    return n_ev


@jit
def snap_detector_close(st, j, thresholds, min_duration, events):
    """Close location ``j``'s open window at its last sample (end of a run); returns the number of event rows."""
    s = st[j]
    return _close_window(s, j, s[_PREV_TENSION], thresholds[j, 0], thresholds[j, 2], min_duration, False, events, 0)


@jit
def snap_detector_step(times, tensions, start, st, thresholds, peak_window, min_duration, crossing, events):
    """Advance every location's state machine over samples ``start..``; stop when ``events`` is full, or after
    a sample that closed a snap event or forgot a spike (so that the guard can rule on it before the samples that
    follow). ``crossing``: the axial wave's crossing of an element (s; 0: no spike is forgotten, _forget_spike).

    times (k,), tensions (k, n_loc), st (n_loc, _N_STATE) state, thresholds (n_loc, 3) = (slack, re-tension,
    snap level). Returns (next sample index, number of event rows written).
    """
    n_ev = 0
    cap = events.shape[0]
    n_loc = tensions.shape[1]
    i = start
    while i < times.shape[0]:
        if n_ev + 2 * n_loc > cap:
            break
        t = times[i]
        snapped = False
        for j in range(n_loc):
            y = tensions[i, j]
            lo = thresholds[j, 0]
            hi = thresholds[j, 1]
            snap_level = thresholds[j, 2]
            s = st[j]
            has_prev = s[_HAS_PREV] > 0.0
            t0 = s[_PREV_T]
            y0 = s[_PREV_TENSION]
            mode = s[_MODE]
            if mode == _RISING:
                # The whole window belongs to this re-tensioning: dips back into slack (chatter,
                # a first weak re-tension) extend the slack period instead of ending the event.
                if y < s[_MIN_T]:
                    s[_MIN_T] = y
                if has_prev and y0 < lo <= y:
                    s[_EXIT_T] = _crossing_time(t0, y0, t, y, lo)
                if has_prev and y0 <= hi < y:
                    s[_FRONT_T] = _crossing_time(t0, y0, t, y, hi)
                if has_prev and y0 <= s[_RESET_Y] < y:
                    s[_RESET_T] = _crossing_time(t0, y0, t, y, s[_RESET_Y])
                third = False
                if y > s[_PEAK]:  # a larger stage: whatever rose after a drop belongs to it
                    _stage_peak(s, 0, t, y)
                    s[_NEXT_RET] = np.nan
                elif np.isnan(s[_DROP_T]):
                    _stage_drop(s, 0, has_prev, t0, y0, t, y, lo)
                elif np.isnan(s[_NEXT_RET]):
                    if y < s[_DROP_MIN]:
                        s[_DROP_MIN] = y
                    if y > hi:
                        _start_next(s, t, y)
                elif y > s[_NEXT_PEAK]:
                    _stage_peak(s, _NEXT, t, y)
                elif np.isnan(s[_NEXT_DROP_T]):
                    _stage_drop(s, _NEXT, has_prev, t0, y0, t, y, lo)
                else:
                    if y < s[_NEXT_DROP_MIN]:
                        s[_NEXT_DROP_MIN] = y
                    # a third re-tensioning: the window's peak is final (two drops into slack behind it)
                    third = y > hi
                # A running maximum that rose from its front in less than an element crossing, with nothing
                # larger for a crossing after it and the tension out of slack since, is numerical: forgotten at
                # once (a re-tensioning after it that never passes it is not swallowed by its window).
                if (crossing > 0.0 and not third and s[_PUBLISHED] == -np.inf and np.isnan(s[_DROP_T])
                        and s[_PEAK] > s[_RESET_Y] and t - s[_PEAK_T] >= crossing
                        and s[_PEAK_T] - s[_PEAK_FRONT] < crossing):
                    n0 = n_ev
                    n_ev = _forget_spike(s, j, t, y, hi, snap_level, min_duration, events, n_ev)
                    snapped = snapped or n_ev > n0
                    mode = s[_MODE]
            if mode == _RISING:
                elapsed = t - s[_RETENSION_T]
                # Close once the window has passed and the running maximum lies behind the current sample;
                # while the tension has stayed out of slack since that maximum, only once the maximum is a
                # whole window old (no larger tension for a window after it): a re-tensioning that rises in
                # stages (a heavy end taken up step by step, one step per axial round trip of the cable,
                # with small dips between them) is one event whose peak is its largest stage. A tension
                # back in slack after the maximum closes at the window's end, and what rose again after
                # that drop continues in its own window (_close_window). A window whose maximum is below the
                # snap level and that has not fallen back into slack stays open: the end is still coming out
                # of slack (a weak first stage, e.g. the ship end holding the hanging cable while the cage
                # end is slack), and the re-tensioning that follows is this slack period's snap. At most 10
                # windows: an end that has not reached the snap level by then left slack without a snap.
                # A window that reached the snap level emits its peak then (a window after it) but stays open
                # while the tension stays out of slack, within the same 10 windows: the slack episode is not
                # over, and a later peak above the one emitted (a first stage just past the snap level, the
                # end taken up fully later, e.g. with the other end) is the snap's new maximum, emitted in
                # turn; ringing after a snap decays and stays below it. The episode's re-tensioning is over
                # once the tension falls back below the re-tension level after a snap is out (the level that
                # ended the slack period): a rise after that is the next cycle of the driving motion, and
                # without a slack period before it no snap (as for a taut end). Not while another location of
                # the cable is still slack in this episode (_slack_elsewhere): the cable has not been taken up,
                # this end holds only the hanging part of it, and a sag of that load is no end of the episode;
                # the take-up of the whole cable that follows is its snap (a new maximum when larger).
                limit = elapsed >= 10.0 * peak_window
                over = s[_PUBLISHED] > -np.inf and y < hi and not _slack_elsewhere(st, j)
                if third or (elapsed >= peak_window and s[_PEAK_T] < t
                             and ((t - s[_PEAK_T] >= peak_window and s[_PEAK] >= snap_level
                                   and s[_PEAK] > s[_PUBLISHED])
                                  or not np.isnan(s[_DROP_T]))) or limit or over:
                    n0 = n_ev
                    n_ev = _close_window(s, j, y, lo, snap_level, min_duration, not (third or limit or over), events,
                                         n_ev)
                    snapped = snapped or (n_ev > n0 and (events[n0, 0] == _SNAP or events[n0, 0] == _NEW_MAXIMUM))
                    if third:
                        _start_next(s, t, y)
                    mode = s[_MODE]
            if mode == _TAUT:
                if y < lo:
                    tc = _crossing_time(t0, y0, t, y, lo) if has_prev and y0 >= lo else t
                    s[_MODE] = _SLACK
                    s[_SLACK_START] = tc
                    s[_MIN_T] = y
                    s[_EXIT_T] = tc
                    s[_PEAK] = -np.inf
                    n_ev = _emit(events, n_ev, 0.0, j, tc, y, y, tc, tc, tc, tc)
            elif mode == _SLACK:
                if y < s[_MIN_T]:
                    s[_MIN_T] = y
                if has_prev and y0 < lo <= y:
                    s[_EXIT_T] = _crossing_time(t0, y0, t, y, lo)
                if y > hi:
                    s[_MODE] = _RISING
                    s[_RETENSION_T] = t
                    s[_PUBLISHED] = -np.inf
                    s[_DROP_T] = np.nan
                    s[_NEXT_RET] = np.nan
                    s[_RESET_Y] = -np.inf
                    s[_RESET_T] = -np.inf
                    s[_FRONT_T] = _crossing_time(t0, y0, t, y, hi) if has_prev and y0 <= hi else t
                    if y > s[_PEAK]:
                        s[_PEAK] = y
                        s[_PEAK_T] = t
                        s[_PEAK_EXIT] = s[_EXIT_T]
                        s[_PEAK_FRONT] = s[_FRONT_T]
            s[_PREV_T] = t
            s[_PREV_TENSION] = y
            s[_HAS_PREV] = 1.0
        i += 1
        if snapped:
            break
    return i, n_ev

"""SIGINT / SIGTERM for the programs that write files (``tether-sim-offline``, ``tether-sim-study``).

A signal must never cut a file in the middle of a write: while a program is writing, the first
SIGINT or SIGTERM only records a stop request (:attr:`SignalStop.requested`), the program's own loop
sees it between two whole units of work (a tick, a finished case), closes its files as at a normal
end, says what it wrote and exits with ``128 + signal number`` (130 for SIGINT, 143 for SIGTERM),
the shell convention. Before the program writes anything (start-up: imports, the numba compile, the
static solve) nothing can be lost, so a signal there stops at once (:class:`KeyboardInterrupt`,
which the program turns into a one-line account). Further signals while stopping are noted on
stderr and otherwise ignored: closing a file takes milliseconds to seconds, never minutes.
"""

import signal
import sys
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class SignalStop:
    """Context manager: SIGINT and SIGTERM handlers for the duration of a ``with`` block.

    ``graceful`` False (start-up): a signal raises KeyboardInterrupt at once. ``graceful`` True
    (writing): a signal sets :attr:`signum`; the program polls :attr:`requested`. The previous
    handlers are restored on exit. Outside the main thread (where Python cannot install handlers)
    it does nothing and :attr:`requested` stays False.
    """

    def __init__(self, program: str, *, graceful: bool = False, stream=None):
        self.program = program
        self.graceful = graceful
        self.signum = None
        self.stream = stream
        self._old = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for sig in SIGNALS:
                self._old[sig] = signal.signal(sig, self._handle)
        return self

    def __exit__(self, *exc_info):
        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old.clear()
        return None

    def _handle(self, signum, _frame):
        repeated = self.signum is not None
        if not repeated:
            self.signum = signum
        if not self.graceful:
            raise KeyboardInterrupt(signal.Signals(signum).name)
        if repeated:
            print(f"{self.program}: {signal.Signals(signum).name} again: already stopping, closing the files "
                  f"(a kill -9 now would leave them incomplete)", file=self.stream or sys.stderr, flush=True)

    @property
    def requested(self) -> bool:
        return self.signum is not None

    @property
    def name(self) -> str:
        return signal.Signals(self.signum).name if self.signum is not None else ""

    @property
    def exit_code(self) -> int:
        """128 + the signal number (130 SIGINT, 143 SIGTERM); 0 when no signal came."""
        return 128 + int(self.signum) if self.signum is not None else 0


def interrupted_code(exc: BaseException, default: int = signal.SIGINT) -> tuple:
    """(signal name, exit code) of a KeyboardInterrupt raised by :class:`SignalStop` (its argument
    is the signal's name) or by Python's own SIGINT handler."""
    name = str(exc.args[0]) if exc.args and str(exc.args[0]) in ("SIGINT", "SIGTERM") else signal.Signals(default).name
    return name, 128 + int(signal.Signals[name])

# SPDX-License-Identifier: GPL-3.0-or-later
"""Progress as the command line shows it, and the machine-readable form ``batch`` reads back from
its child processes (one module both import, so neither imports the other)."""
import time

PROGRESS_PREFIX = "oraclemesh-progress "  # machine-readable progress lines (batch reads them)


class ProgressPrinter:
    """Reports a filter's ProgressEvent: a bar redrawn in place on a terminal, else a line every 10 %,
    or machine-readable lines (``--progress-lines``, read by ``batch``)."""

    def __init__(self, stream, machine=False):
        self.stream, self.machine = stream, machine
        self.tty = not machine and stream.isatty()
        self.last, self.last_time = -1.0, 0.0

    def __call__(self, fraction):
        now = time.monotonic()
        if self.machine or self.tty:
            if fraction - self.last < 0.01 and now - self.last_time < 1.0 and fraction < 1.0:
                return
            if self.machine:
                self.stream.write(f"{PROGRESS_PREFIX}{fraction:.4f}\n")
            else:
                filled = int(30 * fraction)
                self.stream.write(f"\rmeshing [{'#' * filled}{'-' * (30 - filled)}] {100 * fraction:5.1f}%"
                                  + ("\n" if fraction >= 1.0 else ""))
        elif int(10 * fraction) > int(10 * max(self.last, 0)) or self.last < 0:
            self.stream.write(f"meshing: {100 * fraction:.0f}%\n")
        else:
            return
        self.stream.flush()
        self.last, self.last_time = fraction, now

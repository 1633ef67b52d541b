"""The log and the progress line, which share one lock with the result cache."""
import sys
import threading
import time



lock = threading.Lock()


class Progress:
    """One updating line on a terminal (stderr): cases done, elapsed, an estimate of what is left. Nothing
    when stderr is not a terminal, so logs stay clean; log() clears it and draws it again under each message."""

    def __init__(self, total, stream=None, clock=time.time):
        self.stream = stream or sys.stderr
        self.on = total > 0 and self.stream.isatty()
        self.total, self.done, self.clock, self.start = total, 0, clock, clock()

    def text(self):
        elapsed = self.clock() - self.start
        words = f"{self.done}/{self.total} cases, {clock_words(elapsed)} elapsed"
        if 0 < self.done < self.total:
            words += f", about {clock_words(elapsed / self.done * (self.total - self.done))} left"
        return words

    def draw(self):
        if self.on:
            self.stream.write("\r\033[K" + self.text())
            self.stream.flush()

    def clear(self):
        if self.on:
            self.stream.write("\r\033[K")
            self.stream.flush()

    def step(self):
        with lock:
            self.done += 1
            self.draw()

    def finish(self):
        with lock:
            self.clear()
            self.on = False


def clock_words(seconds):
    m, s = divmod(int(round(seconds)), 60)
    return f"{m // 60}:{m % 60:02d}:{s:02d}" if m >= 60 else f"{m}:{s:02d}"


progress = Progress(0)


def start(total):
    """A progress line for `total` cases from now, drawn at once."""
    global progress
    progress = Progress(total)
    progress.draw()


def step():
    progress.step()


def finish():
    progress.finish()


def log(msg):
    with lock:
        progress.clear()
        print(f"[{time.strftime('%H:%M:%S')}] {msg}", flush=True)
        progress.draw()

"""What the Python checks under tests/ share: failures gathered and printed as they come, commands that must
succeed, and the exit status at the end (0 all passed, 1 a failure).

  sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
  from check_support import Failures, run_or_exit
"""
import subprocess


class Failures(list):
    """The failures of one check script, each printed "FAIL: ..." when it comes (the first `shown` of them; None:
    all)."""

    def __init__(self, shown=None):
        super().__init__()
        self.shown = shown

    def fail(self, message):
        self.append(message)
        if self.shown is None or len(self) <= self.shown:
            print("FAIL: " + message)

    def check(self, condition, message):
        if not condition:
            self.fail(message)

    def exit_status(self, passed, failed=None):
        """Prints `passed`, or `failed` (default "N failures") when anything failed; returns the exit status."""
        if self:
            print(failed or f"{len(self)} failures")
            return 1
        print(passed)
        return 0


def run_or_exit(command, **kwargs):
    """Runs `command` with its output captured; a non-zero exit ends the script with both outputs."""
    p = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if p.returncode != 0:
        raise SystemExit(f"FAIL: {' '.join(command)} exited {p.returncode}:\n{p.stdout}\n{p.stderr}")
    return p

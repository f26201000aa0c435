"""The run journal of a label (doc/benchmark-suite.md "Interrupted runs"): every finished row is
appended to RUN_DIR/journal.jsonl as soon as it ends, so a run stopped by Ctrl-C, a kill or the end
of a session keeps what it measured; `suite.sh run --resume` runs only the rows the journal does not
hold (or holds as "sequence generation failed": those are generated again) and reports them all
together.

Line 1 is the run's setup (tier, subset, duration, extra configuration, the two binaries' paths and
the simulator's version): a resume with a different setup is refused, since its rows would not be
comparable. The other lines are {"row": result} (a finished row's figures), {"generated": id, "steps": steps}
(a sequence generated for the row: its steps' wall and CPU seconds, kept even when the run was
interrupted before the row ran) and {"session_wall_s": s, "rows": n} (an invocation that ended,
normally or interrupted).
"""
import json
import os
import threading

FILE_NAME = "journal.jsonl"


class JournalError(Exception):
    pass


class Journal:
    def __init__(self, run_dir, setup, resume):
        self.path = os.path.join(run_dir, FILE_NAME)
        self._lock = threading.Lock()
        self.rows = {}          # row id -> result dict, in the order they ended
        self.generation = {}    # row id -> generation steps (dict name -> {wall_s, cpu_s})
        self.sessions = []      # wall seconds of the earlier invocations
        if resume and os.path.exists(self.path):
            self._load(setup)
        else:
            with open(self.path, "w") as f:
                f.write(json.dumps({"setup": setup}) + "\n")

    def _load(self, setup):
        with open(self.path) as f:
            lines = f.read().splitlines()
        for n, line in enumerate(lines, 1):
            if not line.strip():
                continue
            try:
                entry = json.loads(line)
            except ValueError:
                if n == len(lines):  # the last line cut by a kill: the row is run again
                    break
                raise JournalError(f"{self.path}: line {n} is not JSON")
            if n == 1:
                old = entry.get("setup")
                if old != setup:
                    diff = sorted(k for k in set(old or {}) | set(setup)
                                  if (old or {}).get(k) != setup.get(k))
                    raise JournalError(f"{self.path}: made with another setup ({', '.join(diff)}"
                                       " differ): run without --resume, or with another --label")
            elif "row" in entry:
                if entry["row"].get("status", "").startswith("sequence generation failed"):
                    continue  # the machinery's failure (disk full, ...): generated again
                self.rows[entry["row"]["id"]] = entry["row"]
            elif "generated" in entry:
                self.generation[entry["generated"]] = entry["steps"]
            elif "session_wall_s" in entry:
                self.sessions.append(float(entry["session_wall_s"]))
        # rewrite without a cut last line, so that appends start on a line of their own
        with open(self.path, "w") as f:
            f.write(json.dumps({"setup": setup}) + "\n")
            for rid, steps in self.generation.items():
                f.write(json.dumps({"generated": rid, "steps": steps}) + "\n")
            for res in self.rows.values():
                f.write(json.dumps({"row": res}) + "\n")
            for s in self.sessions:
                f.write(json.dumps({"session_wall_s": s}) + "\n")

    def _append(self, entry):
        with self._lock:
            with open(self.path, "a") as f:
                f.write(json.dumps(entry) + "\n")
                f.flush()
                os.fsync(f.fileno())

    def record_generation(self, row_id, steps):
        with self._lock:
            self.generation[row_id] = steps
        self._append({"generated": row_id, "steps": steps})

    def record_row(self, result):
        with self._lock:
            self.rows[result["id"]] = result
        self._append({"row": result})

    def record_session(self, wall_s, rows):
        self.sessions.append(wall_s)
        self._append({"session_wall_s": wall_s, "rows": rows})

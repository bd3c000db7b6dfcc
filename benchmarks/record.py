"""Run a benchmark and append its result to ``benchmarks/results/<name>.json``.

Every benchmark prints, as its last line, ``key=value`` pairs. This wrapper runs the
command (its output passes through), parses that line, and appends one record with the
date (UTC), the host's CPU, the command and the figures; the Performance page of the
documentation is rendered from these files.

    python benchmarks/record.py NAME -- COMMAND ...
    python benchmarks/record.py settle -- .venv/bin/python benchmarks/settle.py --vs-liggghts
"""
from __future__ import annotations

import datetime
import json
import os
import pathlib
import platform
import shlex
import subprocess
import sys

RESULTS = pathlib.Path(__file__).resolve().parent / "results"


def host() -> str:
    """CPU model and core count (from /proc/cpuinfo), the load average at the start."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{cpu}, {os.cpu_count()} cores, load {load:.1f} at the start"


def parse_last_line(text: str) -> dict:
    """The figures of the last line made of key=value pairs (numbers where they parse)."""
    for line in reversed(text.strip().splitlines()):
        words = line.split()
        if words and all("=" in w for w in words):
            out = {}
            for w in words:
                k, v = w.split("=", 1)
                try:
                    out[k] = int(v)
                except ValueError:
                    try:
                        out[k] = float(v)
                    except ValueError:
                        out[k] = v
            return out
    return {}


def append(name: str, record: dict) -> pathlib.Path:
    path = RESULTS / f"{name}.json"
    data = json.loads(path.read_text()) if path.exists() else {
        "title": name, "script": f"benchmarks/{name}.py", "what": "", "records": []}
    data["records"].append(record)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=1, ensure_ascii=False) + "\n")
    os.replace(tmp, path)
    return path


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if len(argv) < 3 or argv[1] != "--":
        print(__doc__, file=sys.stderr)
        return 2
    name, command = argv[0], argv[2:]
    started = datetime.datetime.now(datetime.timezone.utc)
    where = host()
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, text=True)
    lines = []
    for line in proc.stdout:
        sys.stdout.write(line)
        sys.stdout.flush()
        lines.append(line)
    rc = proc.wait()
    if rc != 0:
        print(f"record: {name} failed (exit {rc}); nothing recorded", file=sys.stderr)
        return rc
    figures = parse_last_line("".join(lines))
    if not figures:
        print(f"record: {name} printed no key=value line; nothing recorded", file=sys.stderr)
        return 1
    cmd = " ".join(shlex.quote(c) for c in command)
    path = append(name, {"date": started.isoformat(timespec="seconds"), "host": where,
                         "command": cmd, "figures": figures, "notes": ""})
    print(f"record: appended to {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

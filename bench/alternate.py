#!/usr/bin/env python3
"""Wall time of a few commands run in turn, so that a VM's drift (another
guest, the CPU's clock) falls on all of them alike, where hyperfine runs one
command's runs back to back. Each command runs once to warm up, then N rounds
of every command, the order reversed every other round.

  bench/alternate.py N 'CMD A' 'CMD B' ...   -> median, mean and min ms of each
"""
import shlex
import statistics
import subprocess
import sys
import time


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rounds, commands = int(sys.argv[1]), sys.argv[2:]
    times = [[] for _ in commands]
    for c in commands:
        subprocess.run(shlex.split(c), check=True)
    for r in range(rounds):
        order = range(len(commands)) if r % 2 == 0 else reversed(range(len(commands)))
        for i in order:
            t0 = time.perf_counter()
            subprocess.run(shlex.split(commands[i]), check=True)
            times[i].append(1000 * (time.perf_counter() - t0))
    for c, t in zip(commands, times):
        print(f"median {statistics.median(t):8.1f}  mean {statistics.mean(t):8.1f}  min {min(t):8.1f} ms  {c}")


if __name__ == "__main__":
    main()

"""Benchmarks of the Python package (docs/benchmarks.md, "Python"): the call overhead against
the library's own time on adams-clearance, and two threads against one on case-study.
Run from the repository root: python python/benchmarks/overhead.py"""

import statistics
import threading
import time

import telescopic


def overhead(scene, repeat=30):
    """Fastest wall time of telescopic.simulate from Python and of the same library call
    timed in Rust, interleaved (s)."""
    python, rust = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        telescopic.simulate(scene)
        python.append(time.perf_counter() - start)
        rust.extend(telescopic._telescopic._time_simulate(scene, 1))
    return min(python), min(rust)


def threads(scene, count):
    """Wall time of `count` simulations on `count` threads at once (s)."""
    workers = [threading.Thread(target=telescopic.simulate, args=(scene,)) for _ in range(count)]
    start = time.perf_counter()
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    return time.perf_counter() - start


if __name__ == "__main__":
    adams = telescopic.Scene.load("scenes/adams-clearance.toml")
    python, rust = overhead(adams)
    print(f"adams-clearance: telescopic.simulate from Python {python * 1e3:.2f} ms, the library "
          f"call in Rust {rust * 1e3:.2f} ms: overhead {100 * (python / rust - 1):.1f} %")
    case = telescopic.Scene.load("scenes/case-study.toml")
    one = min(threads(case, 1) for _ in range(5))
    two = min(threads(case, 2) for _ in range(5))
    print(f"case-study: one simulation {one:.3f} s, two on two threads {two:.3f} s: "
          f"{2 * one / two:.2f}x the throughput")

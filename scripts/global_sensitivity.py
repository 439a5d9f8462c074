"""The full global sensitivity study of issue 28 item 4: >= 10^5 hover orbits, compiled.

Runs :func:`flapping.studies.sensitivity.global_sensitivity` for the six presets at
``--n-base`` base samples each (default 2048: 9 x 2048 = 18 432 orbits a species, 110 592 in
all), prints each species' probabilities and Sobol indices, the failures, and the wall time of
each sweep and of the whole run. The book (appendix "robustness") runs a smaller, stated sample.
Measured on the project's two shared cores (2026-12-03, load 4-7): 110 592 orbits, 556 without a
hover orbit (555 where the hoverfly cannot trim, eq. 40), 110 solved again alone; 302 s of wall
time, 114 s of CPU.

    PYTHONPATH=. python scripts/global_sensitivity.py [--n-base 2048] [--seed 0] [--csv out.csv]
"""

from __future__ import annotations

import argparse
import time
import warnings

import pandas as pd

from flapping.errors import PlausibilityWarning
from flapping.model.presets import PRESETS
from flapping.studies.sensitivity import global_sensitivity


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-base", type=int, default=2048, help="base samples per species")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--csv", help="write the per-species summary here")
    args = parser.parse_args()
    warnings.simplefilter("ignore", PlausibilityWarning)
    pd.set_option("display.width", 160)
    started = time.perf_counter()
    rows, tables = [], []
    for name in PRESETS:
        result = global_sensitivity(name, args.n_base, seed=args.seed)
        rows.append(result.summary())
        table = result.table()[["input", "S1", "S1_conf", "ST", "ST_conf"]]
        table.insert(0, "species", name)
        tables.append(table)
        print(f"{name}: {result.n_orbits} orbits, {result.n_failed} failed "
              f"({result.n_retried} retried alone), "
              f"P(unstable) = {result.p_unstable:.4f} {result.p_unstable_ci}, "
              f"P(oscillatory) = {result.p_oscillatory:.4f} {result.p_oscillatory_ci}, "
              f"sweep {result.wall_time_s:.1f} s", flush=True)
        failures = result.samples.loc[~result.samples["converged"], "message"]
        for message, count in failures.str.split(":").str[0].value_counts().items():
            print(f"    {count} x {message}")
        print(table.to_string(index=False, float_format="%.3f"), flush=True)
    total = time.perf_counter() - started
    summary = pd.DataFrame(rows)
    print(summary.to_string(index=False, float_format="%.4g"))
    print(f"total: {summary['n_orbits'].sum()} orbits, {summary['n_failed'].sum()} failed "
          f"({summary['n_retried'].sum()} retried alone), "
          f"sweeps {summary['wall_time_s'].sum():.1f} s, wall time {total:.1f} s")
    if args.csv:
        pd.concat(tables).to_csv(args.csv, index=False)


if __name__ == "__main__":
    main()

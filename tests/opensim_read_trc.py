"""Reads a TRC the pipeline wrote with OpenSim's own reader (TimeSeriesTableVec3 from a .trc path,
which parses with OpenSim's TRCFileAdapter, as OpenSim's tools do) and checks it
against the truth TRC read the same way: same rate, units, frames, and every marker position the
pipeline filled, but for a few ghosts (at most 1 %), lies within tolerance of some truth marker of
that frame.
usage: opensim_read_trc.py RESULT.trc TRUTH.trc [TOLERANCE_MM]"""
import math
import sys


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    try:
        import opensim
    except ImportError as error:
        print(f"opensim_read_trc: error: cannot import opensim ({error}); run tests/run.sh, which "
              "installs tests/requirements.txt into .venv", file=sys.stderr)
        return 1
    tolerance = float(sys.argv[3]) if len(sys.argv) == 4 else 10.0
    try:
        result = opensim.TimeSeriesTableVec3(sys.argv[1])
        truth = opensim.TimeSeriesTableVec3(sys.argv[2])
    except RuntimeError as error:
        print(f"opensim_read_trc: error: OpenSim cannot read the TRC: {error}", file=sys.stderr)
        return 1

    failures = []
    for key in ("DataRate", "Units"):
        if result.getTableMetaDataAsString(key).strip() != truth.getTableMetaDataAsString(key).strip():
            failures.append(f"{key}: {result.getTableMetaDataAsString(key)} != {truth.getTableMetaDataAsString(key)}")
    if result.getNumRows() < 1 or result.getNumColumns() < 1:
        failures.append(f"empty table: {result.getNumRows()} rows x {result.getNumColumns()} markers")

    truth_times = list(truth.getIndependentColumn())
    filled = 0
    far = 0
    for row in range(result.getNumRows()):
        time = result.getIndependentColumn()[row]
        # The truth row at the same time (TRC times are written with limited decimals).
        match = min(range(len(truth_times)), key=lambda i: abs(truth_times[i] - time))
        if abs(truth_times[match] - time) > 1e-3:
            failures.append(f"row {row}: time {time} has no truth row")
            break
        truth_row = truth.getRowAtIndex(match)
        truth_points = [truth_row[c] for c in range(truth.getNumColumns())]
        truth_points = [(p.get(0), p.get(1), p.get(2)) for p in truth_points if not math.isnan(p.get(0))]
        result_row = result.getRowAtIndex(row)
        for c in range(result.getNumColumns()):
            p = result_row[c]
            if math.isnan(p.get(0)):
                continue
            filled += 1
            nearest = min(math.dist((p.get(0), p.get(1), p.get(2)), t) for t in truth_points)
            far += nearest > tolerance
    if filled == 0:
        failures.append("no marker positions in the result")
    if far > 0.01 * filled:
        failures.append(f"{far} of {filled} positions lie over {tolerance} mm from every truth marker")

    print(f"opensim {opensim.__version__} read {sys.argv[1]}: {result.getNumRows()} rows, "
          f"{result.getNumColumns()} markers, {filled} positions, {far} over {tolerance} mm from the truth")
    for failure in failures:
        print(f"opensim_read_trc: error: {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

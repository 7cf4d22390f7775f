"""The command line of the pipeline tests that run imuconv (npz_numpy.py, validate_schemas.py):
the source tree, the imuconv binary to run, and a scratch directory for what the runs write."""
import argparse
import os


def parse_run_args():
    """--source-dir, --binary and --work-dir, all required; the work directory is made if it
    is not there."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True)
    ap.add_argument("--binary", required=True)
    ap.add_argument("--work-dir", required=True)
    args = ap.parse_args()
    os.makedirs(args.work_dir, exist_ok=True)
    return args

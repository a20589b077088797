#!/usr/bin/env python3
"""Snakemake's cluster-status command of the Slurm profile (config.yaml, `cluster-status`).

Usage: status.py JOBID   (as `sbatch --parsable` prints it: ID, or ID;CLUSTER)
Prints one word: running, success or failed.

Without a status command Snakemake waits for a marker file that the job script writes when it
ends by itself: a job that Slurm ends (time limit, memory limit, node failure, scancel) writes
none, and Snakemake would wait for it forever. This asks Slurm instead: scontrol first (the
controller keeps a finished job for MinJobAge, 300 s by default; no accounting needed), then
sacct (the accounting database, where the cluster has one). A job that neither knows any more
is reported as success: Snakemake then checks the job's outputs and fails the job if they are
missing. An error of scontrol other than an unknown job (a busy controller) is reported as
running, so that the job is asked about again.
"""
import re
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED",
           "REQUEUE_FED", "REQUEUE_HOLD", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED",
           "RESV_DEL_HOLD"}


def ask(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as e:
        return subprocess.CompletedProcess(cmd, 1, "", str(e))


def state_from_scontrol(jobid, cluster):
    """The job's state, None when the controller no longer knows it; raises on other errors."""
    r = ask(["scontrol"] + (["-M", cluster] if cluster else []) + ["show", "job", "-o", jobid])
    if r.returncode == 0:
        m = re.search(r"\bJobState=(\S+)", r.stdout)
        if m:
            return m.group(1)
    if "invalid job id" in (r.stderr + r.stdout).lower():
        return None
    raise RuntimeError("scontrol show job %s: %s" % (jobid, (r.stderr or r.stdout).strip()))


def state_from_sacct(jobid, cluster):
    """The job's state from accounting, None without accounting or without a record."""
    r = ask(["sacct"] + (["-M", cluster] if cluster else []) +
            ["-X", "-n", "-P", "-o", "State", "-j", jobid])
    lines = [l.split()[0] for l in r.stdout.splitlines() if l.strip()] if r.returncode == 0 else []
    return lines[-1] if lines else None


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: status.py JOBID\n")
        return 2
    jobid, _, cluster = argv[1].strip().partition(";")
    try:
        state = state_from_scontrol(jobid, cluster)
    except RuntimeError as e:
        sys.stderr.write("status.py: %s (asking again later)\n" % e)
        print("running")
        return 0
    if state is None:
        state = state_from_sacct(jobid, cluster)
    if state is None or state == "COMPLETED":
        print("success")
    elif state in RUNNING:
        print("running")
    else:  # FAILED, TIMEOUT, CANCELLED, OUT_OF_MEMORY, NODE_FAIL, PREEMPTED, BOOT_FAIL, DEADLINE, ...
        print("failed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

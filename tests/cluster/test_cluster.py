"""Renders split over a scheduler (docs/cluster.md): shards, a killed one, merge.

Two flows give the bytes of one plain render:
- plain processes, two at a time, one of them killed with SIGKILL after its first checkpoint
  and run again with --resume;
- a one-node Slurm cluster on localhost (slurmctld and slurmd with a config written here,
  auth/none, ports of its own): docs/cluster/shard.sbatch as a job array, one task's render
  killed, Slurm requeueing it (RequeueExit=137), docs/cluster/merge.sbatch after the array.
"""

import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import time

import pytest

SOURCE = pathlib.Path(os.environ.get("FIXPOINT_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("FIXPOINT_BIN", str(SOURCE / "build" / "bin" / "fixpoint"))
DOCS = SOURCE / "docs" / "cluster"
SHARDS = 4
# Long enough on one thread (a few seconds) to be killed after its first checkpoint.
POINTS = "240000000"


def config(tmp):
    """The render: paper 01's fig. 4a, smaller, with more points on each pixel."""
    path = tmp / "fig4a.yaml"
    text = (SOURCE / "configs" / "inversion" / "fig4a.yaml").read_text()
    for key, value in (("width", "200"), ("height", "200"), ("points", POINTS)):
        text, n = re.subn(rf"^(  {key}:) .*$", rf"\g<1> {value}", text, count=1, flags=re.M)
        assert n == 1, key
    path.write_text(text)
    return path


def plain(tmp, cfg):
    out = tmp / "plain.png"
    subprocess.run([CLI, "render", "-q", str(cfg), "-o", str(out), "--threads", "2"], check=True)
    return out.read_bytes()


def wait_for(what, test, seconds, proc=None):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if test():
            return
        if proc is not None and proc.poll() is not None:
            break
        time.sleep(0.05)
    pytest.fail("timed out waiting for " + what)


def test_the_job_scripts_parse():
    for script in ("shard.sbatch", "merge.sbatch"):
        r = subprocess.run(["bash", "-n", str(DOCS / script)], capture_output=True, text=True)
        assert r.returncode == 0, script + ": " + r.stderr


def test_plain_processes_with_a_killed_shard_give_the_plain_bytes(tmp_path):
    cfg = config(tmp_path)
    want = plain(tmp_path, cfg)
    parts = tmp_path / "parts"
    parts.mkdir()

    def shard(k, resume=False):
        ck = parts / f"part-{k}.ck"
        keep = ["--resume", str(ck)] if resume else ["--checkpoint", str(ck), "--checkpoint-every", "0.3s"]
        return [CLI, "render", "-q", str(cfg), "--shard", f"{k}/{SHARDS}", "--histogram",
                str(parts / f"part-{k}.fph"), "--threads", "1"] + keep

    # Shard 2 killed once its first checkpoint is there; shard 1 beside it runs to its end.
    victim = subprocess.Popen(shard(2))
    other = subprocess.Popen(shard(1))
    wait_for("shard 2's first checkpoint", (parts / "part-2.ck").exists, 120, victim)
    victim.send_signal(signal.SIGKILL)
    assert victim.wait() == -signal.SIGKILL, "shard 2 ended before it was killed"
    assert not (parts / "part-2.fph").exists()
    assert other.wait() == 0
    for k in (3, 4):
        subprocess.run(shard(k), check=True)
    # Only the lost piece again: shard 2 continues from its checkpoint.
    subprocess.run(shard(2, resume=True), check=True)
    merged = tmp_path / "merged.png"
    files = [str(parts / f"part-{k}.fph") for k in (4, 2, 3, 1)]
    subprocess.run([CLI, "merge", "-q"] + files + ["-o", str(merged)], check=True)
    assert merged.read_bytes() == want


def free_ports(n):
    socks = [socket.socket() for _ in range(n)]
    for s in socks:
        s.bind(("127.0.0.1", 0))
    ports = [s.getsockname()[1] for s in socks]
    for s in socks:
        s.close()
    return ports


SLURM = shutil.which("slurmctld") or (os.path.exists("/usr/sbin/slurmctld") and "/usr/sbin/slurmctld")


@pytest.mark.skipif(not SLURM, reason="no Slurm (Debian: slurmctld slurmd slurm-client): Slurm flow skipped")
def test_a_slurm_job_array_with_a_killed_task_gives_the_plain_bytes(tmp_path):
    cfg = config(tmp_path)
    want = plain(tmp_path, cfg)
    host = socket.gethostname()
    ctld_port, d_port = free_ports(2)
    state = tmp_path / "slurm"
    for d in ("state", "spool"):
        (state / d).mkdir(parents=True)
    conf = state / "slurm.conf"
    # One node, this machine; no munge (auth/none: the cluster lives and dies with the test).
    # RequeueExit: a task whose render was killed (exit 137) goes back into the queue.
    conf.write_text(
        f"""ClusterName=fixpoint-test
SlurmctldHost={host}(127.0.0.1)
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmdUser=root
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
StateSaveLocation={state}/state
SlurmdSpoolDir={state}/spool
SlurmctldPidFile={state}/slurmctld.pid
SlurmdPidFile={state}/slurmd.pid
SlurmctldLogFile={state}/slurmctld.log
SlurmdLogFile={state}/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
JobRequeue=1
RequeueExit=137
NodeName={host} NodeAddr=127.0.0.1 CPUs={os.cpu_count() or 1} State=UNKNOWN
PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=str(conf))
    daemons = []

    def slurm(*args):
        return subprocess.run(list(args), env=env, check=True, capture_output=True, text=True).stdout

    def log(name):
        p = state / name
        return p.read_text() if p.exists() else "(no log)"

    try:
        for cmd in (["/usr/sbin/slurmctld", "-D", "-c", "-i"], ["/usr/sbin/slurmd", "-D", "-c", "-N", host]):
            daemons.append(subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT))

        def idle():
            r = subprocess.run(["sinfo", "-h", "-o", "%t"], env=env, capture_output=True, text=True)
            return r.returncode == 0 and r.stdout.strip() == "idle"

        wait_for("the Slurm node to be idle", idle, 60)
        work = tmp_path / "work"
        work.mkdir()
        job_env = f"ALL,CONFIG={cfg},FIXPOINT={CLI},EVERY=0.3s,PARTS={work}/parts"
        array = slurm("sbatch", "--parsable", f"--array=1-{SHARDS}", "-D", str(work), "-o", f"{work}/shard-%a.log",
                      f"--export={job_env}", str(DOCS / "shard.sbatch")).strip()
        merge = slurm("sbatch", "--parsable", f"--dependency=afterany:{array}", "-D", str(work), "-o",
                      f"{work}/merge.log", f"--export=ALL,FIXPOINT={CLI},OUT={work}/merged.png,PARTS={work}/parts",
                      str(DOCS / "merge.sbatch")).strip()
        ck = work / "parts" / "part-2.ck"

        def task_2_went_wrong():
            # (Ended without a checkpoint: its log says why.)
            r = subprocess.run(["squeue", "-h", "-j", f"{array}_2"], env=env, capture_output=True, text=True)
            log2 = work / "shard-2.log"
            if r.returncode == 0 and r.stdout.strip() == "" and not ck.exists():
                pytest.fail("task 2 ended without a checkpoint: " + (log2.read_text() if log2.exists() else ""))
            return ck.exists()

        wait_for("task 2's first checkpoint", task_2_went_wrong, 180)

        def render_of_task_2():
            r = subprocess.run(["pgrep", "-f", f"{work}/parts/part-2.fph"], capture_output=True, text=True)
            return [int(p) for p in r.stdout.split()]

        pids = render_of_task_2()
        assert pids, "task 2's render ended before it could be killed"
        for p in pids:
            os.kill(p, signal.SIGKILL)

        # Requeued by Slurm; a requeued task waits about two minutes before it is eligible
        # again, so the test makes it eligible now.
        def requeued():
            info = slurm("scontrol", "show", "job", f"{array}_2")
            return "Restarts=1" in info and "JobState=PENDING" in info

        wait_for("Slurm to requeue task 2", requeued, 60)
        slurm("scontrol", "update", f"jobid={array}_2", "StartTime=now")

        def merged():
            r = subprocess.run(["squeue", "-h", "-j", merge], env=env, capture_output=True, text=True)
            return r.returncode == 0 and r.stdout.strip() == ""

        wait_for("the merge job", merged, 300)
        log2 = (work / "shard-2.log").read_text() if (work / "shard-2.log").exists() else ""
        out = work / "merged.png"
        assert out.exists(), "no image; merge said: " + (work / "merge.log").read_text() + log2
        assert out.read_bytes() == want
    except subprocess.CalledProcessError as e:
        pytest.fail(f"{e.cmd}: {e.stderr}\n{log('slurmctld.log')[-2000:]}")
    finally:
        subprocess.run(["scancel", "--full", "-u", "root"], env=env, capture_output=True)
        for d in daemons:
            d.terminate()
        for d in daemons:
            try:
                d.wait(10)
            except subprocess.TimeoutExpired:
                d.kill()

"""`mpirun -np N fixpoint render`: the rank count changes nothing in the bytes written.

Every render here is compared byte for byte with the same render on one process (no mpirun),
on 1, 2, 3 and 4 ranks of this one machine (--oversubscribe: more ranks than cores).
"""

import os
import pathlib
import shutil
import signal
import subprocess
import time

import pytest

SOURCE = pathlib.Path(os.environ.get("FIXPOINT_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("FIXPOINT_BIN", str(SOURCE / "build" / "bin" / "fixpoint"))
MPIRUN = shutil.which("mpirun")

BUILT = os.environ.get("FIXPOINT_MPI_BUILT") != "0"

if MPIRUN is None:
    pytest.skip("no mpirun (Debian: openmpi-bin): MPI tests skipped", allow_module_level=True)


@pytest.fixture(autouse=True)
def needs_mpi_build(request):
    if not BUILT and "without_mpi" not in request.node.name:
        pytest.skip("this build has no MPI (FIXPOINT_MPI off or libopenmpi-dev missing): skipped")

RANKS = (1, 2, 3, 4)


def mpi_env():
    env = dict(os.environ)
    # Containers often forbid the cross-memory attach Open MPI's shared-memory transport tries
    # first; copying through shared memory works everywhere. Root (CI) must be allowed.
    env["OMPI_MCA_btl_vader_single_copy_mechanism"] = "none"
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    env["OMPI_MCA_rmaps_base_oversubscribe"] = "1"
    return env


def mpirun(n, *args, cwd=None):
    cmd = [MPIRUN, "-np", str(n), "--oversubscribe", CLI, *map(str, args)]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, env=mpi_env(), timeout=600)


def plain(*args, cwd=None):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=600)


def content(path):
    """A file's bytes (no time of writing in them: EXR's capDate and TIFF's DateTime are empty)."""
    return path.read_bytes()


def same_on_every_rank_count(tmp_path, config, *sets, threads=2, ext="png"):
    one = tmp_path / f"one.{ext}"
    r = plain("render", config, "-o", one, "--quiet", "--threads", threads, *sets)
    assert r.returncode == 0, r.stderr
    for n in RANKS:
        out = tmp_path / f"np{n}.{ext}"
        r = mpirun(n, "render", config, "-o", out, "--quiet", "--threads", threads, *sets)
        assert r.returncode == 0, f"{n} ranks: {r.stderr}"
        assert content(out) == content(one), f"{n} ranks: the bytes differ from one process"
    return one


def sets(**kv):
    out = []
    for k, v in kv.items():
        out += ["--set", f"renderer.{k}={v}"]
    return out


def test_chaos_game_density(tmp_path):
    # Paper 01 Fig. 6(a), the default render: 3000 chains, split over the ranks by blocks.
    same_on_every_rank_count(tmp_path, SOURCE / "configs/inversion/fig6a.yaml",
                             *sets(width=256, height=256, points=2000000))


def test_chaos_game_last_colour(tmp_path):
    # flame's set-colour mode: each pixel keeps its last point's colour by (step, chain); the
    # ranks' winners merge by the same order.
    same_on_every_rank_count(tmp_path, SOURCE / "configs/inversion/fig4a.yaml",
                             *sets(width=200, height=200, points=1000000))


def test_chaos_game_uneven_threads(tmp_path):
    # The blocks are cut alike whatever each rank's thread count: 1 and 3 threads per rank.
    config = SOURCE / "configs/iterations/fig6b.yaml"
    s = sets(width=160, height=160, points=500000)
    one = same_on_every_rank_count(tmp_path, config, *s, threads=1)
    out = tmp_path / "t3.png"
    r = mpirun(3, "render", config, "-o", out, "--quiet", "--threads", 3, *s)
    assert r.returncode == 0, r.stderr
    assert out.read_bytes() == one.read_bytes()


def same_in_pieces_on_ranks(tmp_path, config, pieces, *sets):
    """Rendered beyond the memory budget (1 thread and 12 MiB a rank) on 2 and 3 ranks, in
    `pieces` ("strips", "bands"): the same bytes as one process rendering the whole image."""
    one = tmp_path / "one.png"
    r = plain("render", config, "-o", one, "--quiet", "--threads", 2, *sets)
    assert r.returncode == 0, r.stderr
    for n in (2, 3):
        out = tmp_path / f"np{n}.png"
        r = mpirun(n, "render", config, "-o", out, "--threads", 1, "--memory", f"{12 * n}M", *sets)
        assert r.returncode == 0, f"{n} ranks: {r.stderr}"
        assert f" {pieces} of " in r.stderr, r.stderr
        assert out.read_bytes() == one.read_bytes(), f"{n} ranks in {pieces}: the bytes differ from one process"


def test_chaos_game_strips_on_ranks(tmp_path):
    # Every strip's chains split over the ranks, as a whole render's.
    same_in_pieces_on_ranks(tmp_path, SOURCE / "configs/inversion/fig6a.yaml", "strips",
                            *sets(width=400, height=400, points=1000000))


def test_orbit_trap_bands_on_ranks(tmp_path):
    # Each band's tiles dealt to the ranks as a whole render deals them.
    same_in_pieces_on_ranks(tmp_path, SOURCE / "configs/orbit-trap/fig6a.yaml", "bands",
                            *sets(width=1600, height=1200))


def test_orbit_trap(tmp_path):
    same_on_every_rank_count(tmp_path, SOURCE / "configs/orbit-trap/fig5a.yaml",
                             *sets(width=120, height=120))


def test_orbit_trap_float_exr(tmp_path):
    # Float output: every bit of every pixel, not 8-bit values.
    same_on_every_rank_count(tmp_path, SOURCE / "configs/orbit-trap/fig6a.yaml",
                             *sets(width=96, height=80), ext="exr")


def test_superfractal(tmp_path):
    same_on_every_rank_count(tmp_path, SOURCE / "configs/gumowski-mira/fig2-F.yaml",
                             *sets(width=200, height=200, points_per_buffer=300000, steps=8))


def test_superfractal_colour_stealing(tmp_path):
    same_on_every_rank_count(tmp_path, SOURCE / "configs/gumowski-mira/colour-stealing.yaml",
                             *sets(width=160, height=160, points_per_buffer=200000, steps=8))


def test_mfs(tmp_path):
    same_on_every_rank_count(tmp_path, SOURCE / "configs/mfs/fig4-middle.yaml", *sets(width=200, height=200))


def test_vary_spreads_children(tmp_path):
    config = SOURCE / "configs/inversion/fig6a.yaml"
    s = sets(width=96, height=96, points=200000)
    vary = ["--vary", "renderer.seed=1..5"]
    # (Relative names: the sheet's recipe names its children's files.)
    r = plain("render", config, "-o", "one.png", "--quiet", *vary, *s, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    for n in (2, 3):
        d = tmp_path / f"np{n}"
        d.mkdir()
        r = mpirun(n, "render", config, "-o", "one.png", *vary, *s, cwd=d)
        assert r.returncode == 0, r.stderr
        for name in ["one.png"] + [f"one-{k}.png" for k in range(1, 6)]:
            assert (d / name).read_bytes() == (tmp_path / name).read_bytes(), f"{n} ranks: {name}"
        # Rank 0 speaks for the job: one line per child and one for the sheet.
        assert r.stderr.count("renderer.seed=") == 5, r.stderr
        assert r.stderr.count("contact sheet of 5 children") == 1, r.stderr


def test_summary_from_rank_0_only(tmp_path):
    out = tmp_path / "a.png"
    r = mpirun(3, "render", SOURCE / "configs/inversion/fig6a.yaml", "-o", out,
               *sets(width=64, height=64, points=100000))
    assert r.returncode == 0, r.stderr
    lines = [l for l in r.stderr.splitlines() if l.startswith(str(out))]
    assert len(lines) == 1 and "3 ranks x " in lines[0], r.stderr


def test_bad_config_is_one_line(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("renderer:\n  type: chaos-game\n  width: -5\n  maps: []\n")
    r = mpirun(3, "render", cfg, "-o", tmp_path / "x.png")
    assert r.returncode != 0
    ours = [l for l in r.stderr.splitlines() if l.startswith(str(cfg))]
    assert len(ours) == 1, r.stderr
    assert ours[0].startswith(f"{cfg}:3:"), ours[0]
    assert not (tmp_path / "x.png").exists()


SCHEME = """\
import os
{at_load}
def step(T, x, y, n):
    {at_step}
    return T(x, y)
"""


def scheme_config(tmp_path, at_load="", at_step="pass"):
    (tmp_path / "s.py").write_text(SCHEME.format(at_load=at_load, at_step=at_step))
    cfg = tmp_path / "c.yaml"
    cfg.write_text((SOURCE / "configs/iterations/fig6b.yaml").read_text().replace(
        "iteration: {type: mann, alpha: 0.7}", "iteration: {type: python-scheme, file: s.py}"))
    return cfg


def test_a_rank_that_fails_its_checks(tmp_path):
    # Rank 2 alone cannot load the scheme: every rank stops before rendering, and rank 0 prints
    # rank 2's error line, once.
    cfg = scheme_config(tmp_path, at_load='if os.environ["OMPI_COMM_WORLD_RANK"] == "2": raise OSError("no disk on this node")')
    r = mpirun(4, "render", cfg, "-o", tmp_path / "x.png", *sets(points=20000), cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    ours = [l for l in r.stderr.splitlines() if "no disk on this node" in l]
    assert len(ours) == 1 and ours[0].startswith(str(cfg)), r.stderr
    assert not (tmp_path / "x.png").exists()


def test_ranks_with_different_recipes_are_refused(tmp_path):
    # MPMD: rank 1 with another seed (as a node with another copy of the config would be). Each
    # rank alone passes its checks; together they would write an image of two recipes that
    # neither reproduces. Refused by every rank before any work, in one line.
    cfg = SOURCE / "configs/inversion/fig6a.yaml"
    out = tmp_path / "x.png"
    common = ["render", str(cfg), "-o", str(out), "--quiet", *sets(width=64, height=64, points=20000)]
    cmd = [MPIRUN, "--oversubscribe", "-np", "1", CLI, *common, "--set", "renderer.seed=1", ":",
           "-np", "1", CLI, *common, "--set", "renderer.seed=2"]
    r = subprocess.run(cmd, capture_output=True, text=True, env=mpi_env(), timeout=600)
    assert r.returncode == 2, r.stderr
    ours = [l for l in r.stderr.splitlines() if "another recipe" in l]
    assert ours == ["fixpoint: rank 1 of 2 would render another recipe than rank 0 (another config, --set, "
                    "seed or plugin build on its machine): every rank must render the same; nothing rendered"], \
        r.stderr
    assert not out.exists()
    # The same seed on both: rendered.
    cmd = [a if a != "renderer.seed=2" else "renderer.seed=1" for a in cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, env=mpi_env(), timeout=600)
    assert r.returncode == 0, r.stderr
    assert out.exists()


def test_a_rank_that_fails_mid_render(tmp_path):
    # Rank 1's scheme raises during the render: the job ends with its error line and no file.
    cfg = scheme_config(tmp_path, at_step='if os.environ["OMPI_COMM_WORLD_RANK"] == "1": raise RuntimeError("node lost")')
    r = mpirun(3, "render", cfg, "-o", tmp_path / "x.png", *sets(points=400000), cwd=tmp_path)
    assert r.returncode != 0
    ours = [l for l in r.stderr.splitlines() if "node lost" in l]
    assert len(ours) == 1 and ours[0].startswith("fixpoint: rank 1 of 3: "), r.stderr
    assert not (tmp_path / "x.png").exists()


def test_a_rank_that_fails_mid_render_prints_only_its_line(tmp_path):
    # The other ranks, stopped by mpirun, add no "interrupted" of their own (they did, one
    # line each); with mpirun's --quiet, Open MPI's banner is gone too: the whole of stderr is
    # the one line, and the exit code the failing rank's.
    cfg = scheme_config(tmp_path, at_step='if os.environ["OMPI_COMM_WORLD_RANK"] == "1": raise RuntimeError("node lost")')
    cmd = [MPIRUN, "--quiet", "-np", "3", "--oversubscribe", CLI, "render", str(cfg), "-o", str(tmp_path / "x.png"),
           *sets(points=400000)]
    r = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path, env=mpi_env(), timeout=600)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("fixpoint: rank 1 of 3: ") and "node lost" in lines[0], r.stderr
    assert "interrupted" not in r.stderr


def test_ctrl_c_to_mpirun_prints_one_line(tmp_path):
    # mpirun passes a Ctrl-C on as SIGTERM to every rank: rank 0 alone says it, once, and no
    # file is left. mpirun itself exits 1 after a SIGINT whatever the ranks return (Open MPI
    # 4.1; docs/large-renders.md): only its being non-zero is asserted.
    cmd = [MPIRUN, "--quiet", "-np", "3", "--oversubscribe", CLI, "render", str(SOURCE / "configs/inversion/fig6a.yaml"),
           "-o", str(tmp_path / "x.png"), "--threads", "1", *sets(points=2000000000)]
    p = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, cwd=tmp_path, env=mpi_env())
    time.sleep(6)  # every rank is past its start and rendering (a render of minutes)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode != 0
    assert err.splitlines() == ["fixpoint: interrupted; no image written"], err
    assert os.listdir(tmp_path) == []


def test_a_rank_that_fails_mid_stream(tmp_path):
    # The same beyond the memory budget: rank 0 is writing the image as the strips come, and
    # the job's end leaves neither the image nor its temporary file.
    cfg = scheme_config(tmp_path, at_step='if os.environ["OMPI_COMM_WORLD_RANK"] == "1" and n > 50: raise RuntimeError("node lost")')
    before = set(os.listdir(tmp_path))
    r = mpirun(3, "render", cfg, "-o", tmp_path / "x.png", "--memory", "24M", "--threads", 1,
               *sets(points=400000, width=400, height=400), cwd=tmp_path)
    assert r.returncode != 0
    ours = [l for l in r.stderr.splitlines() if "node lost" in l]
    assert len(ours) == 1 and ours[0].startswith("fixpoint: rank 1 of 3: "), r.stderr
    assert set(os.listdir(tmp_path)) == before, sorted(set(os.listdir(tmp_path)) - before)


def test_other_commands_run_once(tmp_path):
    r = mpirun(3, "validate", SOURCE / "configs/inversion/fig6a.yaml")
    assert r.returncode == 0, r.stderr
    assert r.stderr.count("valid:") == 1, r.stderr


def test_memory_check_counts_the_ranks_on_this_machine(tmp_path):
    # The ranks on one machine each hold their buffers: the check before the render shares the
    # budget among them (6 MiB over 3 ranks: 2 MiB each, below a strip of one 4000-pixel row).
    r = mpirun(3, "render", SOURCE / "configs/inversion/fig6a.yaml", "-o", tmp_path / "x.png", "--threads", 1,
               "--memory", "6M", *sets(width=4000, height=4000))
    assert r.returncode == 2, r.stderr
    ours = [l for l in r.stderr.splitlines() if "render needs" in l]
    assert len(ours) == 1 and "with 1 thread(s), in strips of one row on each of 3 ranks; --memory gives 6.0 MiB" \
        in ours[0], r.stderr
    assert not (tmp_path / "x.png").exists()


def test_a_killed_job_resumes_from_each_ranks_checkpoint(tmp_path):
    # Each rank keeps its share's state in ck.bin.K-of-N. One rank killed with SIGKILL after
    # every rank's first checkpoint ends the job; --resume on the same rank count continues it
    # to the bytes of one process.
    config = SOURCE / "configs/inversion/fig6a.yaml"
    job = sets(points=300000000, width=200, height=200)
    one = tmp_path / "one.png"
    r = plain("render", config, "-o", one, "--quiet", "--threads", 2, *job)
    assert r.returncode == 0, r.stderr
    ck = tmp_path / "ck.bin"
    out = tmp_path / "x.png"
    cmd = [MPIRUN, "--quiet", "-np", "2", "--oversubscribe", CLI, "render", str(config), "-o", str(out), "--quiet",
           "--threads", "1", "--checkpoint", str(ck), "--checkpoint-every", "0.3s", *job]
    p = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True, cwd=tmp_path, env=mpi_env())
    mine = [tmp_path / "ck.bin.1-of-2", tmp_path / "ck.bin.2-of-2"]
    end = time.monotonic() + 300
    while not all(f.exists() for f in mine) and p.poll() is None and time.monotonic() < end:
        time.sleep(0.05)
    assert p.poll() is None, "the job ended before its ranks were killed: " + p.stderr.read()
    pids = subprocess.run(["pgrep", "-f", str(ck)], capture_output=True, text=True).stdout.split()
    ranks = [int(x) for x in pids if int(x) != p.pid]
    assert ranks, "no rank to kill"
    os.kill(max(ranks), signal.SIGKILL)
    p.communicate(timeout=120)
    assert p.returncode != 0
    assert not out.exists()
    r = mpirun(2, "render", config, "-o", out, "--threads", 1, "--resume", ck, *job)
    assert r.returncode == 0, r.stderr
    assert "(each rank to its own)" in r.stderr, r.stderr
    assert content(out) == content(one)


def test_checkpoints_resume_on_their_rank_count_only(tmp_path):
    config = SOURCE / "configs/inversion/fig6a.yaml"
    ck = tmp_path / "ck.bin"
    r = mpirun(2, "render", config, "-o", tmp_path / "x.png", "--quiet", "--checkpoint", ck, *sets(points=20000))
    assert r.returncode == 0, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["ck.bin.1-of-2", "ck.bin.2-of-2", "x.png"]
    before = sorted(os.listdir(tmp_path))
    r = mpirun(3, "render", config, "-o", tmp_path / "y.png", "--resume", ck, *sets(points=40000))
    assert r.returncode == 2, r.stderr
    ours = [line for line in r.stderr.splitlines() if "--resume" in line]
    assert ours == [f"--resume: no checkpoint '{ck}.1-of-3' of rank 1 of 3: '{ck}' was checkpointed on 2 ranks: "
                    "resume it with mpirun -np 2"], r.stderr
    # One process is not a rank of two either.
    r = plain("render", config, "-o", tmp_path / "y.png", "--resume", tmp_path / "ck.bin.1-of-2", *sets(points=40000))
    assert r.returncode == 2 and "# rank 1 of 2" in r.stderr, r.stderr
    assert sorted(os.listdir(tmp_path)) == before


def test_without_mpi_a_build_refuses_ranks(tmp_path):
    # (Runs in a build without MPI only; the sanitizer build of CI is one.)
    if BUILT:
        pytest.skip("this build has MPI")
    r = mpirun(2, "render", SOURCE / "configs/inversion/fig6a.yaml", "-o", tmp_path / "x.png")
    assert r.returncode == 2
    assert "fixpoint: launched as 2 MPI ranks, but this build has no MPI" in r.stderr, r.stderr
    assert not (tmp_path / "x.png").exists()


def test_chaos_game_finished(tmp_path):
    # The finishing stage (docs/finishing.md) on rank 0 after the ranks' exact sum: supersampled,
    # filtered and density-estimated, whole and in strips, the same bytes as one process.
    stage = sets(supersample=2, estimator_radius=2) + ["--set", "renderer.filter={type: gaussian, radius: 0.75}"]
    config = SOURCE / "configs/inversion/fig6a.yaml"
    same_on_every_rank_count(tmp_path, config, *sets(width=200, height=200, points=1000000), *stage)
    same_in_pieces_on_ranks(tmp_path, config, "strips", *sets(width=400, height=400, points=1000000), *stage)


def test_chaos_game_kept_histogram(tmp_path):
    # render --histogram under mpirun (docs/histograms.md): rank 0 writes the ranks' summed
    # histogram, the same file as one process's, and tone finishes it to the full render's bytes.
    config = SOURCE / "configs/inversion/fig4a.yaml"
    s = sets(width=160, height=160, points=400000)
    r = plain("render", config, "-o", tmp_path / "one.png", "--quiet", "--histogram", tmp_path / "one.fph", *s)
    assert r.returncode == 0, r.stderr
    for n in (2, 3):
        r = mpirun(n, "render", config, "-o", tmp_path / f"np{n}.png", "--quiet", "--histogram",
                   tmp_path / f"np{n}.fph", *s)
        assert r.returncode == 0, f"{n} ranks: {r.stderr}"
        assert content(tmp_path / f"np{n}.fph") == content(tmp_path / "one.fph"), f"{n} ranks"
    toned = ["--set", "renderer.estimator_radius=3", "--set", "renderer.colourer.gamma=3"]
    r = plain("tone", tmp_path / "np3.fph", "-o", tmp_path / "toned.png", "--quiet", *toned)
    assert r.returncode == 0, r.stderr
    r = plain("render", config, "-o", tmp_path / "full.png", "--quiet", *s, *toned)
    assert r.returncode == 0, r.stderr
    assert content(tmp_path / "toned.png") == content(tmp_path / "full.png")


def test_chaos_game_palette(tmp_path):
    # flam3's palette index (docs/palettes.md): each chain's index from its own colour stream,
    # the ranks' sums the same as one process's.
    same_on_every_rank_count(tmp_path, SOURCE / "configs/palettes/fern.yaml",
                             *sets(width=200, height=200, points=1000000))


def test_quality_rounds_on_ranks(tmp_path):
    # render --quality under mpirun (docs/histograms.md): each round is a job of all the ranks,
    # rank 0 counts the level and tells the others; whole (the rounds' images kept in memory) and
    # in strips (each round streamed into temporary files that take their names in the last
    # round), the image and the kept histogram are one process's, and no round leaves a file.
    config = SOURCE / "bench/sierpinski.yaml"
    s = sets(width=400, height=300, points=20000, supersample=2)
    r = plain("render", config, "-o", tmp_path / "one.png", "--quiet", "--quality", 5, "--histogram",
              tmp_path / "one.fph", *s)
    assert r.returncode == 0, r.stderr
    for n, memory in ((2, []), (3, ["--memory", "20M"])):
        out = tmp_path / f"np{n}"
        out.mkdir()
        r = mpirun(n, "render", config, "-o", out / "q.png", "--quality", 5, "--histogram", out / "q.fph",
                   *memory, *s)
        assert r.returncode == 0, f"{n} ranks: {r.stderr}"
        assert ("strips of" in r.stderr) == bool(memory), r.stderr
        assert r.stderr.count("after 6 rounds") == 1, r.stderr
        assert sorted(p.name for p in out.iterdir()) == ["q.fph", "q.png"], f"{n} ranks: a round's file left"
        assert content(out / "q.png") == content(tmp_path / "one.png"), f"{n} ranks"
        assert content(out / "q.fph") == content(tmp_path / "one.fph"), f"{n} ranks"

#!/usr/bin/env python3
"""The preview page's re-toning latency (docs/histograms.md): `fixpoint serve` renders a config
once, keeping its histogram; each later text that changes only finishing parameters (gamma,
the filter, the density estimation) is finished from that histogram. This times, over several
changes, the seconds from the POST of the new text to the whole PNG received (what the page
waits for), and the finish alone (X-Seconds: the render job's time, without the PNG's encoding).

Usage: bench/retone.py BUILD/bin/fixpoint CONFIG [REPEATS]   (prints one line per setting)
The target (issue 42): a change shows in under 100 ms at 1024^2."""

import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request


def main():
    binary, config = sys.argv[1], sys.argv[2]
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 7
    text = open(config).read()
    with tempfile.TemporaryDirectory() as root:
        proc = subprocess.Popen([binary, "serve", "--port", "0", "--root", root], stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True)
        url = re.match(r"fixpoint serve: open (http://[^/]+/)", proc.stdout.readline()).group(1)

        def post(body):
            req = urllib.request.Request(url + "api/preview", data=json.dumps(body).encode(), method="POST",
                                         headers={"Content-Type": "application/json"})
            with urllib.request.urlopen(req, timeout=600) as r:
                return json.loads(r.read())

        def last_frame(job):
            after = -1
            while True:
                with urllib.request.urlopen(url + f"api/frame?job={job}&after={after}", timeout=600) as r:
                    if r.status == 204:
                        continue
                    body = r.read()
                    if r.headers["X-Done"] == "1":
                        return r.headers, body
                    after = int(r.headers["X-Stage"])

        try:
            t0 = time.perf_counter()
            h, _ = last_frame(post({"text": text})["job"])
            print(f"first render: {time.perf_counter() - t0:.2f} s ({h['X-Width']}x{h['X-Height']})")
            settings = {
                "background": lambda g: text.replace("renderer:\n", f"renderer:\n  background: [0, 0, {g / 100}]\n",
                                                     1),
                "density estimation": lambda g: text.replace("renderer:\n",
                                                             f"renderer:\n  estimator_radius: {2 + g / 10}\n", 1),
            }
            for name, make in settings.items():
                walls, posts, finishes = [], [], []
                for k in range(repeats):
                    t0 = time.perf_counter()
                    started = post({"text": make(k + 1)})
                    posts.append(time.perf_counter() - t0)
                    assert started.get("retoned"), started
                    h, png = last_frame(started["job"])
                    walls.append(time.perf_counter() - t0)
                    finishes.append(float(h["X-Seconds"]))
                ms = lambda v: f"{statistics.median(v) * 1000:.0f} ms"  # noqa: E731
                print(f"{name}: request to PNG {ms(walls)} (min {min(walls) * 1000:.0f}): the text checked and "
                      f"planned {ms(posts)}, the finish {ms(finishes)}, the PNG and its transfer the rest; "
                      f"{h['X-Width']}x{h['X-Height']}, {os.cpu_count()} cores")
        finally:
            proc.terminate()
            proc.wait()


if __name__ == "__main__":
    main()

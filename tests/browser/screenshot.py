"""The README's picture of the preview page: `fixpoint serve` on paper 01's Fig. 4(a), in
headless Chromium, once the preview has reached its last stage.

    /usr/bin/python3 tests/browser/screenshot.py build/bin/fixpoint docs/gallery/serve-page.png
"""

import os
import pathlib
import shutil
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))


def main(cli, out):
    os.environ["FIXPOINT_BIN"] = str(pathlib.Path(cli).resolve())
    import conftest  # reads FIXPOINT_BIN
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        shutil.copy(conftest.CONFIG, root / "fig4a.yaml")
        server = conftest.Server(root, "fig4a.yaml")
        opts = webdriver.ChromeOptions()
        opts.binary_location = conftest.CHROMIUM
        for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1500,860",
                  "--force-device-scale-factor=1", "--hide-scrollbars"):
            opts.add_argument(a)
        driver = webdriver.Chrome(service=Service(conftest.CHROMEDRIVER), options=opts)
        try:
            page = conftest.Page(driver, server.url, root)
            page.wait_done()
            driver.save_screenshot(str(out))
        finally:
            driver.quit()
            server.stop()
    print(f"wrote {out}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])

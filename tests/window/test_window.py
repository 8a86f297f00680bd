"""--window end to end under a virtual X server (Xvfb) on the machine's
Vulkan device (lavapipe here): frames presented through a real swapchain
under the validation layer, the X display's pixels against --save-frame,
a resize from outside that makes the swapchain anew, Esc and SIGTERM
closing a --frames 0 run, and the exit code without a display."""

import csv
import ctypes
import json
import os
import re
import shutil
import signal
import subprocess
import time

import numpy as np
import pytest

from rtbench import schema

EXIT_BAD_INPUT = 2
EXIT_NO_DEVICE = 3
WIDTH, HEIGHT = 96, 64
DEADLINE_S = 60  # generous: lavapipe under ASan on two shared cores

# A window of ours, as xwininfo lists the root's children: id, title, size.
WINDOW_LINE = re.compile(r'^\s+(0x[0-9a-f]+) "(raytracer - [^"]*)":.*?\s(\d+)x(\d+)\+-?\d+\+-?\d+', re.M)


def window_built(raytracer) -> bool:
    done = subprocess.run([raytracer, "--version"], capture_output=True, text=True, check=True)
    return "Window (--window): GLFW" in done.stdout


@pytest.fixture(scope="module")
def windowed(raytracer):
    if not window_built(raytracer):
        pytest.skip("this build has no window (RT_WINDOW=OFF)")
    return raytracer


@pytest.fixture
def display():
    """A private Xvfb on a display number it picks itself (-displayfd): no
    clash with other tests or a desktop, no TCP listener. -noreset: an X
    server resets when its last client leaves, and a client that connects
    during the reset is refused; the tests' xwininfo polls connect and
    leave while the raytracer starts, so without it the raytracer's window
    sometimes failed to open ("Failed to open display")."""
    if shutil.which("Xvfb") is None:
        pytest.fail("Xvfb is missing (Debian: apt-get install xvfb; scripts/setup-debian installs it)")
    read_end, write_end = os.pipe()
    server = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_end), "-screen", "0", "640x480x24", "-nolisten", "tcp", "-noreset"],
        pass_fds=(write_end,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_end)
    with os.fdopen(read_end) as ready:
        number = ready.readline().strip()
    assert number.isdigit(), "Xvfb did not report its display"
    try:
        yield f":{number}"
    finally:
        server.terminate()
        server.wait(timeout=10)


def env_for(display):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["DISPLAY"] = display
    return env


def read_csv(path):
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def still_scene(repo_root, tmp_path):
    """scenes/default.json with the camera held still: frame k is the same
    picture for every k, so a screenshot taken at any moment shows frame k."""
    scene = json.loads((repo_root / "scenes/default.json").read_text())
    scene["camera"]["orbitVelocity"] = 0.0
    path = tmp_path / "still.json"
    path.write_text(json.dumps(scene))
    return path


def our_window(display):
    """(id, title, width, height) of the raytracer's window, or None."""
    listing = subprocess.run(["xwininfo", "-root", "-children", "-display", display], capture_output=True, text=True)
    match = WINDOW_LINE.search(listing.stdout)
    return None if match is None else (int(match[1], 16), match[2], int(match[3]), int(match[4]))


def wait_for_frames_shown(display, process):
    """Until the title shows a frame time (set after the first presented frame)."""
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline:
        assert process.poll() is None, process.communicate()[1]
        window = our_window(display)
        if window is not None and window[1].endswith(" ms"):
            return window
        time.sleep(0.1)
    pytest.fail("the window never showed a frame")


def wait_for_size(display, width, height):
    deadline = time.monotonic() + DEADLINE_S
    while time.monotonic() < deadline:
        window = our_window(display)
        if window is not None and window[2:] == (width, height):
            return window
        time.sleep(0.1)
    pytest.fail(f"the window never became {width}x{height}")


def rgb_pixels(image_arg, width, height):
    """An image file ImageMagick reads (xwd:FILE, FILE.png) as an HxWx3 uint8 array."""
    raw = subprocess.run(["convert", image_arg, "-depth", "8", "rgb:-"], capture_output=True, check=True).stdout
    return np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)


def screenshot(display, window_id, width, height, tmp_path):
    """The window's pixels as the X server holds them (xwd)."""
    shot = tmp_path / "window.xwd"
    subprocess.run(["xwd", "-silent", "-display", display, "-id", hex(window_id), "-out", shot], check=True)
    return rgb_pixels(f"xwd:{shot}", width, height)


def agree(a, b):
    """docs/render-model.md section 8: >= 99.5 % of pixels within 2 in each of
    R, G, B, and PSNR >= 40 dB over R, G, B."""
    diff = np.abs(a.astype(np.int32) - b.astype(np.int32))
    close = np.mean(np.all(diff <= 2, axis=2))
    mse = np.mean(diff.astype(np.float64) ** 2)
    psnr = float("inf") if mse == 0 else 10 * np.log10(255.0**2 / mse)
    return close >= 0.995 and psnr >= 40.0


class X11:
    """The two requests a window manager or a user would make: resize the
    window, press a key in it (libX11 and the XTEST extension via ctypes)."""

    def __init__(self, display):
        self.x11 = ctypes.CDLL("libX11.so.6")
        self.xtst = ctypes.CDLL("libXtst.so.6")
        self.x11.XOpenDisplay.restype = ctypes.c_void_p
        self.x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
        for name in ("XFlush", "XCloseDisplay"):
            getattr(self.x11, name).argtypes = [ctypes.c_void_p]
        self.x11.XResizeWindow.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_uint, ctypes.c_uint]
        self.x11.XSetInputFocus.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_int, ctypes.c_ulong]
        self.x11.XKeysymToKeycode.argtypes = [ctypes.c_void_p, ctypes.c_ulong]
        self.xtst.XTestFakeKeyEvent.argtypes = [ctypes.c_void_p, ctypes.c_uint, ctypes.c_int, ctypes.c_ulong]
        self.dpy = self.x11.XOpenDisplay(display.encode())
        assert self.dpy, f"cannot open X display {display}"

    def resize(self, window_id, width, height):
        self.x11.XResizeWindow(self.dpy, window_id, width, height)
        self.x11.XFlush(self.dpy)

    def press_escape(self, window_id):
        escape = self.x11.XKeysymToKeycode(self.dpy, 0xFF1B)  # XK_Escape
        self.x11.XSetInputFocus(self.dpy, window_id, 1, 0)  # RevertToPointerRoot, CurrentTime
        for down in (1, 0):
            self.xtst.XTestFakeKeyEvent(self.dpy, escape, down, 0)
        self.x11.XFlush(self.dpy)

    def close(self):
        self.x11.XCloseDisplay(self.dpy)


def start_until_closed(raytracer, scene, tmp_path, display, *extra):
    args = [
        raytracer,
        "--window",
        "--frames",
        "0",
        "--warmup",
        "0",
        scene,
        "--width",
        WIDTH,
        "--height",
        HEIGHT,
        "--csv",
        tmp_path / "run.csv",
        "--vk-validation",
        "--quiet",
        *extra,
    ]
    return subprocess.Popen(
        list(map(str, args)), env=env_for(display), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def finish(process):
    _out, err = process.communicate(timeout=DEADLINE_S)
    assert process.returncode == 0, err
    assert "vulkan warning" not in err and "vulkan error" not in err, err
    return err


@pytest.mark.parametrize("renderer", ["--gpu", "--simd"])
def test_frames_are_presented_under_validation(windowed, repo_root, tmp_path, display, renderer):
    frames, warmup = 6, 2
    done = subprocess.run(
        list(
            map(
                str,
                [
                    windowed,
                    renderer,
                    repo_root / "scenes/default.json",
                    "--window",
                    "--width",
                    WIDTH,
                    "--height",
                    HEIGHT,
                    "--warmup",
                    warmup,
                    "--frames",
                    frames,
                    "--csv",
                    tmp_path / "run.csv",
                    "--vk-validation",
                    "--quiet",
                ],
            )
        ),
        env=env_for(display),
        capture_output=True,
        text=True,
        timeout=DEADLINE_S * 2,
    )
    assert done.returncode == 0, done.stderr
    # Not one validation message; the loader's own (a foreign architecture's
    # driver manifests on a multiarch machine) are printed as "vulkan loader".
    validation = [line for line in done.stderr.splitlines() if line.startswith(("vulkan error", "vulkan warning"))]
    assert validation == [], done.stderr
    rows = read_csv(tmp_path / "run.csv")
    assert [int(r["frame"]) for r in rows] == list(range(warmup + frames))
    assert {r["present"] for r in rows} == {"window"}
    for r in rows:
        assert 0.0 <= float(r["acquire_ms"]) <= float(r["present_ms"]), "the acquire wait is part of Present"
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    window = meta["window"]
    assert window["frames_presented"] == warmup + frames
    assert window["present_mode"] == "fifo" and window["present_mode_granted"] == "fifo"
    assert window["swapchain_images"] >= 2
    assert window["closed"] is False
    assert meta["config"]["present"] == "window"
    assert meta["device"]["validation"] is True
    assert schema.metadata_key_problems(meta) == []


@pytest.mark.parametrize("mode", ["mailbox", "immediate"])
def test_present_mode_asked_for_and_granted_are_recorded(windowed, repo_root, tmp_path, display, mode):
    done = subprocess.run(
        list(
            map(
                str,
                [
                    windowed,
                    "--sequential",
                    repo_root / "scenes/default.json",
                    "--window",
                    "--present-mode",
                    mode,
                    "--width",
                    32,
                    "--height",
                    24,
                    "--warmup",
                    0,
                    "--frames",
                    3,
                    "--csv",
                    tmp_path / "run.csv",
                    "--quiet",
                ],
            )
        ),
        env=env_for(display),
        capture_output=True,
        text=True,
        timeout=DEADLINE_S,
    )
    assert done.returncode == 0, done.stderr
    window = json.loads((tmp_path / "run.meta.json").read_text())["window"]
    assert window["present_mode"] == mode
    # Granted is what the surface offers: the mode itself, else FIFO (the one every surface has).
    assert window["present_mode_granted"] in (mode, "fifo")


@pytest.mark.parametrize("renderer", ["--gpu", "--sequential"])
def test_the_display_shows_the_saved_frame_until_sigterm_closes_the_window(
    windowed, repo_root, tmp_path, display, renderer
):
    saved = tmp_path / "frame0.png"
    process = start_until_closed(
        windowed, still_scene(repo_root, tmp_path), tmp_path, display, renderer, "--save-frame", f"0:{saved}"
    )
    try:
        window_id, _, width, height = wait_for_frames_shown(display, process)
        assert (width, height) == (WIDTH, HEIGHT), "the window has the render size"
        shown = screenshot(display, window_id, WIDTH, HEIGHT, tmp_path)
    finally:
        process.send_signal(signal.SIGTERM)
    finish(process)
    frame = rgb_pixels(str(saved), WIDTH, HEIGHT)
    assert agree(shown, frame), "the window shows the frame --save-frame wrote"
    # The comparison can fail: red and blue swapped (a copy into the BGRA
    # swapchain image instead of a blit) or rows upside down do not agree.
    assert not agree(shown, frame[:, :, ::-1])
    assert not agree(shown, frame[::-1])
    rows = read_csv(tmp_path / "run.csv")
    assert len(rows) >= 1 and [int(r["frame"]) for r in rows] == list(range(len(rows))), "every frame recorded"
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["window"]["closed"] is True
    assert meta["config"]["measured_frames"] == 0


def test_a_resize_makes_the_swapchain_anew_and_esc_closes(windowed, repo_root, tmp_path, display):
    saved = tmp_path / "frame0.png"
    process = start_until_closed(
        windowed, still_scene(repo_root, tmp_path), tmp_path, display, "--gpu", "--save-frame", f"0:{saved}"
    )
    x11 = X11(display)
    try:
        window_id = wait_for_frames_shown(display, process)[0]
        x11.resize(window_id, 2 * WIDTH, 2 * HEIGHT)
        wait_for_size(display, 2 * WIDTH, 2 * HEIGHT)
        time.sleep(1.0)  # frames at the new size
        shown = screenshot(display, window_id, 2 * WIDTH, 2 * HEIGHT, tmp_path)
        x11.press_escape(window_id)
        finish(process)
    finally:
        x11.close()
        if process.poll() is None:
            process.kill()
    meta = json.loads((tmp_path / "run.meta.json").read_text())
    assert meta["window"]["swapchain_recreations"] >= 1
    assert meta["window"]["closed"] is True, "Esc closed it"
    # Twice the size: the blit scaled every pixel to a 2x2 block.
    frame = rgb_pixels(str(saved), WIDTH, HEIGHT)
    assert agree(shown[::2, ::2], frame)


def test_no_display_exits_3_and_windowless_runs_go_on(windowed, repo_root, tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    base = [
        windowed,
        "--gpu",
        repo_root / "scenes/default.json",
        "--width",
        32,
        "--height",
        24,
        "--warmup",
        0,
        "--frames",
        2,
    ]
    done = subprocess.run(
        list(map(str, [*base, "--window", "--csv", tmp_path / "window.csv"])),
        env=env,
        capture_output=True,
        text=True,
        timeout=DEADLINE_S,
    )
    assert done.returncode == EXIT_NO_DEVICE, done.stderr
    assert "no window" in done.stderr and "no display" in done.stderr, done.stderr
    assert not (tmp_path / "window.csv").exists(), "nothing rendered, nothing written"
    done = subprocess.run(
        list(map(str, [*base, "--csv", tmp_path / "plain.csv", "--quiet"])),
        env=env,
        capture_output=True,
        text=True,
        timeout=DEADLINE_S,
    )
    assert done.returncode == 0, done.stderr
    assert {r["present"] for r in read_csv(tmp_path / "plain.csv")} == {"upload"}
    assert {r["acquire_ms"] for r in read_csv(tmp_path / "plain.csv")} == {""}


@pytest.mark.parametrize(
    "args, option",
    [
        (["--present-mode", "mailbox"], "--present-mode needs --window"),
        (["--frames", "0"], "--frames 0 (run until the window is closed) needs --window"),
        (["--window", "--present", "upload"], "excludes --present upload"),
        (["--window", "--present-mode", "vsync"], "--present-mode"),
    ],
)
def test_window_options_without_their_window_are_bad_input(raytracer, repo_root, args, option):
    done = subprocess.run(
        [str(raytracer), "--sequential", str(repo_root / "scenes/default.json"), *args], capture_output=True, text=True
    )
    assert done.returncode == EXIT_BAD_INPUT, done.stderr
    assert option in done.stderr.splitlines()[-1]

"""Noise warnings: governor, load and spread, on fake inputs."""

import math

from rtbench import noise


def _fake_sysfs(root, governors):
    for i, g in enumerate(governors):
        d = root / f"cpu{i}" / "cpufreq"
        d.mkdir(parents=True)
        (d / "scaling_governor").write_text(g + "\n")
    (root / "cpufreq").mkdir()  # not a CPU: ignored


def test_governor_not_performance_is_named(tmp_path):
    _fake_sysfs(tmp_path, ["performance", "powersave"])
    governors = noise.read_governors(tmp_path)
    assert governors == {"cpu0": "performance", "cpu1": "powersave"}
    (warning,) = noise.governor_warnings(governors)
    assert "powersave" in warning and "1 of 2" in warning


def test_performance_governor_or_none_readable_gives_no_warning(tmp_path):
    _fake_sysfs(tmp_path, ["performance", "performance"])
    assert noise.governor_warnings(noise.read_governors(tmp_path)) == []
    assert noise.governor_warnings(noise.read_governors(tmp_path / "nothing")) == []


def test_load_warning_threshold():
    assert noise.load_warnings(0.2, 2) == []
    assert noise.load_warnings(None, 2) == []
    assert "load average is 1.50" in noise.load_warnings(1.5, 2)[0]
    assert noise.load_warnings(1.5, 16) == []


def test_spread_warning_lists_the_noisiest_first():
    (w,) = noise.spread_warnings({"a": 0.01, "b": 0.30, "c": 0.08, "d": math.nan})
    assert w.startswith("2 configuration(s)") and w.index("b (30.0%)") < w.index("c (8.0%)")
    assert noise.spread_warnings({"a": 0.01}) == []

"""Emulated runs: an aarch64 build run on x86-64 under qemu-user measures the
emulator, not a machine (23x slower for sequential, 220x for simd_only on
our 2-core AMD: not even uniformly so), so its
timings must not reach a table as speed. Two guards: the bench runner
refuses a binary of another architecture than this machine's before it
starts, and the loader refuses a run whose metadata says it was emulated
(host.emulation), whoever made it."""

from __future__ import annotations

import platform
from pathlib import Path

from rtbench import names

# ELF e_machine values (the System V ABI's registry) of the architectures we build for.
_ELF_MACHINES = {62: "x86_64", 183: "aarch64"}
# platform.machine()'s spellings of them.
_HOST_MACHINES = {"x86_64": "x86_64", "amd64": "x86_64", "aarch64": "aarch64", "arm64": "aarch64"}


def binary_architecture(binary: Path) -> str | None:
    """The architecture an ELF executable was built for; None for another
    file or an architecture we do not build for."""
    with open(binary, "rb") as f:
        header = f.read(20)
    if len(header) < 20 or header[:4] != b"\x7fELF":
        return None
    order = "little" if header[5] == 1 else "big"
    return _ELF_MACHINES.get(int.from_bytes(header[18:20], order))


def host_architecture() -> str:
    machine = platform.machine()
    return _HOST_MACHINES.get(machine.lower(), machine)


def foreign_binary_reason(binary: Path) -> str | None:
    """Why `binary` would run emulated here (it is built for another
    architecture), or None where it runs natively."""
    built_for = binary_architecture(binary)
    host = host_architecture()
    if built_for is None or built_for == host:
        return None
    return (
        f"{binary} is an {built_for} binary and this machine is {host}: it would run under an emulator, "
        f"whose timings are no machine's speed; run the bench on an {built_for} machine"
    )


def emulated_run_reason(meta_path: Path, meta: dict) -> str | None:
    """Why the run of this metadata sidecar cannot be read as speed (it ran
    emulated), or None for a native run."""
    emulation = (meta.get(names.META_HOST) or {}).get(names.HOST_EMULATION)
    if not emulation:
        return None
    emulator = emulation.get(names.EMULATOR) or "an emulator"
    cpu = emulation.get(names.EMULATED_CPU)
    on = f" emulating {cpu}" if cpu else ""
    return (
        f"{meta_path}: an emulated run ({emulator}{on} on {emulation.get(names.EMULATION_HOST_ARCHITECTURE)}): "
        "its timings are no machine's speed; rerun natively"
    )

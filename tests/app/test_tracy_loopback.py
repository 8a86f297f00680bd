"""Loopback only: the Tracy-enabled binary (preset profile) listens on
127.0.0.1 and nowhere else, and opens no UDP socket (the stock client
listens on every interface and broadcasts over UDP; cmake/Tracy.cmake
defines TRACY_ONLY_LOCALHOST and TRACY_NO_BROADCAST against that).

The sockets of a process are read from the kernel: the inodes of its
socket descriptors (/proc/PID/fd) matched against the tables of
/proc/net/{tcp,tcp6,udp,udp6,udplite,udplite6,raw,raw6}. The reader is first
pointed at sockets this test opens itself on 0.0.0.0, so that it is shown
to see what it must reject."""

import os
import socket
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

TABLES = ("tcp", "tcp6", "udp", "udp6", "udplite", "udplite6", "raw", "raw6")
TCP_LISTEN = "0A"  # the kernel's TCP_LISTEN state, as /proc/net/tcp writes it
LOOPBACK = "127.0.0.1"


@dataclass(frozen=True)
class InetSocket:
    table: str  # tcp, tcp6, udp, ...
    address: str
    port: int
    listening: bool


def socket_inodes(pid: int) -> set[int]:
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:  # closed since the listing
            continue
        if target.startswith("socket:["):
            inodes.add(int(target[len("socket:[") : -1]))
    return inodes


def decode_address(hex_address: str) -> str:
    """/proc/net writes an address as the hex of its 32-bit words in host
    order (little-endian here)."""
    raw = bytes.fromhex(hex_address)
    words = b"".join(raw[i : i + 4][::-1] for i in range(0, len(raw), 4))
    return socket.inet_ntop(socket.AF_INET if len(raw) == 4 else socket.AF_INET6, words)


def inet_sockets(pid: int) -> list[InetSocket]:
    """Every IPv4/IPv6 socket (TCP, UDP, UDP-Lite, raw) the process holds."""
    inodes = socket_inodes(pid)
    found = []
    for table in TABLES:
        path = Path(f"/proc/{pid}/net/{table}")
        if not path.exists():
            continue
        for line in path.read_text().splitlines()[1:]:
            fields = line.split()
            if int(fields[9]) not in inodes:
                continue
            address, port = fields[1].split(":")
            found.append(
                InetSocket(
                    table, decode_address(address), int(port, 16), table.startswith("tcp") and fields[3] == TCP_LISTEN
                )
            )
    return found


def wait_for_listener(proc: subprocess.Popen, timeout: float = 60) -> list[InetSocket]:
    """The process's sockets once it listens on something (Tracy's listener
    starts on a thread of its own shortly after start-up)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"the raytracer exited early ({proc.returncode}): {proc.stderr.read()}"
        sockets = inet_sockets(proc.pid)
        if any(s.listening for s in sockets):
            return sockets
        time.sleep(0.05)
    pytest.fail(f"the Tracy-enabled raytracer did not listen on any TCP port within {timeout:.0f} s")


def test_the_socket_reader_sees_a_listener_on_every_interface_and_udp():
    with (
        socket.socket(socket.AF_INET, socket.SOCK_STREAM) as tcp,
        socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as udp,
        socket.socket(socket.AF_INET6, socket.SOCK_STREAM) as tcp6,
    ):
        tcp.bind(("0.0.0.0", 0))
        tcp.listen()
        udp.bind(("0.0.0.0", 0))
        tcp6.bind(("::1", 0))
        tcp6.listen()
        mine = inet_sockets(os.getpid())
        assert InetSocket("tcp", "0.0.0.0", tcp.getsockname()[1], True) in mine
        assert InetSocket("udp", "0.0.0.0", udp.getsockname()[1], False) in mine
        assert InetSocket("tcp6", "::1", tcp6.getsockname()[1], True) in mine
    assert decode_address("0100007F") == LOOPBACK


def test_tracy_enabled_binary_listens_on_loopback_only_and_opens_no_udp_socket(repo_root, tracy_raytracer):
    # Enough frames to outlive the check; it is killed at the end.
    proc = subprocess.Popen(
        [
            tracy_raytracer,
            "--sequential",
            repo_root / "scenes/default.json",
            "--width",
            "32",
            "--height",
            "24",
            "--warmup",
            "0",
            "--frames",
            "1000000",
            "--quiet",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        cwd=repo_root,
    )
    try:
        wait_for_listener(proc)
        time.sleep(0.5)  # let any later socket (a broadcast one) appear too
        sockets = inet_sockets(proc.pid)
    finally:
        proc.kill()
        proc.wait()
    assert [s for s in sockets if s.listening], sockets
    assert [s for s in sockets if s.table.startswith("tcp") and s.address != LOOPBACK] == []
    assert [s for s in sockets if not s.table.startswith("tcp")] == [], "no UDP or raw socket"

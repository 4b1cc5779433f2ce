"""End to end: results that travel. One workspace runs the pipeline and pushes to a DVC remote; a
fresh clone pulls and reruns nothing. Real parts: a local folder remote, and an SSH remote served
by a real OpenSSH server on localhost, started and stopped here (dvc-ssh plugin)."""

from __future__ import annotations

import shutil
import socket
import subprocess
import time
from pathlib import Path

import pytest

from tools.repository import dvc, git
from workspaces import committed_run


@pytest.fixture(scope="module")
def pushed_run(tmp_path_factory, small_seed_cache) -> Path:
    """A workspace that ran the pipeline (its stages restored from the seed's run cache), with
    dvc.lock committed."""
    return committed_run(tmp_path_factory.mktemp("origin") / "repo", small_seed_cache)


def pull_into_a_fresh_clone(origin: Path, clone: Path, remote_name: str, *local_settings: tuple[str, ...]) -> None:
    """Clone `origin` (git), give the clone its own `dvc remote modify --local` settings, pull its
    outputs from the remote it pushed to, and check that nothing reruns and the metrics are the
    origin's."""
    assert git(origin.parent, "clone", "-q", str(origin), str(clone)).returncode == 0
    for setting in local_settings:
        assert dvc(clone, "remote", "modify", "--local", remote_name, *setting).returncode == 0
    pulled = dvc(clone, "pull", "-r", remote_name)
    assert pulled.returncode == 0, pulled.stdout[-2000:] + pulled.stderr[-2000:]
    status = dvc(clone, "status")
    assert status.returncode == 0 and "up to date" in status.stdout, status.stdout
    rerun = dvc(clone, "repro")
    assert rerun.returncode == 0 and "Running stage" not in rerun.stdout, rerun.stdout
    assert dvc(clone, "metrics", "show").stdout == dvc(origin, "metrics", "show").stdout
    assert (clone / "plots/report.html").read_bytes() == (origin / "plots/report.html").read_bytes()


@pytest.mark.e2e
def test_a_folder_remote_carries_a_run_to_a_fresh_clone(pushed_run, tmp_path):
    store = tmp_path / "store"
    assert dvc(pushed_run, "remote", "add", "folder", str(store)).returncode == 0
    git(pushed_run, "commit", "-qam", "remote")
    pushed = dvc(pushed_run, "push", "-r", "folder")
    assert pushed.returncode == 0, pushed.stderr
    pull_into_a_fresh_clone(pushed_run, tmp_path / "clone", "folder")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture
def sshd(tmp_path):
    """A real OpenSSH server on localhost for this test only: its own host key, one user key, a
    port of its own; stopped afterwards. Skipped where sshd is not installed."""
    daemon = shutil.which("sshd") or ("/usr/sbin/sshd" if Path("/usr/sbin/sshd").is_file() else None)
    if daemon is None:
        pytest.skip("OpenSSH server (sshd) is not installed: apt-get install openssh-server (.ci/run does)")
    pytest.importorskip("dvc_ssh", reason="the dvc-ssh plugin is not installed (pip install dvc-ssh)")
    keys = tmp_path / "ssh"
    keys.mkdir(mode=0o700)
    for name in ("host", "user"):
        subprocess.run(["ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-f", str(keys / name)], check=True)
    (keys / "authorized_keys").write_text((keys / "user.pub").read_text())
    (keys / "authorized_keys").chmod(0o600)
    port = free_port()
    config = keys / "sshd_config"
    config.write_text(
        f"Port {port}\nListenAddress 127.0.0.1\nHostKey {keys / 'host'}\nPidFile {keys / 'sshd.pid'}\n"
        f"AuthorizedKeysFile {keys / 'authorized_keys'}\nPasswordAuthentication no\nStrictModes no\n"
        "UsePAM no\nPermitRootLogin prohibit-password\nSubsystem sftp internal-sftp\n"
    )
    Path("/run/sshd").mkdir(exist_ok=True)  # privilege separation directory sshd insists on
    server = subprocess.Popen([daemon, "-D", "-e", "-f", str(config)], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        with socket.socket() as probe:
            if probe.connect_ex(("127.0.0.1", port)) == 0:
                break
        time.sleep(0.1)
    else:
        server.kill()
        pytest.fail(f"sshd did not start: {server.stderr.read() if server.stderr else ''}")
    yield port, keys / "user"
    server.terminate()
    server.wait(timeout=10)


@pytest.mark.e2e
def test_an_ssh_remote_carries_a_run_to_a_fresh_clone(pushed_run, sshd, tmp_path):
    port, key = sshd
    user = subprocess.run(["id", "-un"], capture_output=True, text=True, check=True).stdout.strip()
    url = f"ssh://{user}@127.0.0.1:{port}{tmp_path / 'store'}"
    for command in (
        ("remote", "add", "ssh", url),
        # the key and the host check are the user's own settings: --local keeps them out of git
        ("remote", "modify", "--local", "ssh", "keyfile", str(key)),
    ):
        assert dvc(pushed_run, *command).returncode == 0
    git(pushed_run, "commit", "-qam", "ssh remote")
    pushed = dvc(pushed_run, "push", "-r", "ssh")
    assert pushed.returncode == 0, pushed.stdout[-2000:] + pushed.stderr[-2000:]
    pull_into_a_fresh_clone(pushed_run, tmp_path / "clone", "ssh", ("keyfile", str(key)))


@pytest.mark.e2e
def test_an_experiment_run_on_one_machine_is_read_on_another(pushed_run, tmp_path):
    """docs/sharing.md's big-machine workflow on small data: clone A runs an experiment and pushes
    it (git ref to the shared repository, outputs to the DVC remote); clone B pulls and applies it."""
    store = tmp_path / "store"
    assert dvc(pushed_run, "remote", "add", "-d", "shared", str(store)).returncode == 0
    git(pushed_run, "commit", "-qam", "default remote")
    assert dvc(pushed_run, "push").returncode == 0
    big = tmp_path / "big"
    assert git(tmp_path, "clone", "-q", str(pushed_run), str(big)).returncode == 0
    assert dvc(big, "pull").returncode == 0
    ran = dvc(big, "exp", "run", "-n", "bigger", "-S", "pca.n_keep=10")
    assert ran.returncode == 0, ran.stdout[-2000:] + ran.stderr[-2000:]
    pushed = dvc(big, "exp", "push", "origin", "bigger")
    assert pushed.returncode == 0, pushed.stdout[-2000:] + pushed.stderr[-2000:]
    laptop = tmp_path / "laptop"
    assert git(tmp_path, "clone", "-q", str(pushed_run), str(laptop)).returncode == 0
    pulled = dvc(laptop, "exp", "pull", "origin", "bigger")
    assert pulled.returncode == 0, pulled.stdout[-2000:] + pulled.stderr[-2000:]
    assert dvc(laptop, "exp", "apply", "bigger").returncode == 0
    assert dvc(laptop, "metrics", "show").stdout == dvc(big, "metrics", "show").stdout
    assert (laptop / "plots/report.html").read_bytes() == (big / "plots/report.html").read_bytes()
    status = dvc(laptop, "status")
    assert status.returncode == 0 and "up to date" in status.stdout, status.stdout

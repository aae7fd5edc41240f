"""The workbench's server is safe to leave running: it answers only its own page, counts a job until its
thread ends, shoots off the event loop, and stops on Ctrl-C with one line."""

from __future__ import annotations

import asyncio
import json
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from starlette.testclient import TestClient

from analytic.design_file import default_design, design_to_dict
from workbench import app as workbench_app
from workbench.app import build_app
from workbench.guard import split_host
from workbench.jobs import Jobs, TooMany

ROOT = Path(__file__).resolve().parents[1]
PORT = 8765
#: How long a stopped server may take to exit, s: ``workbench.__main__.STOP_SECONDS`` for the requests
#: still open, and the interpreter's exit, with room for a loaded machine.
STOP_WAIT = 20.0


def tables() -> dict:
    return json.loads(json.dumps(design_to_dict(default_design())))


def client_at(host: str) -> TestClient:
    """A client that reaches the server at ``host`` (an address, as a URL writes it) on ``PORT``."""
    return TestClient(build_app(), base_url=f"http://{host}:{PORT}", raise_server_exceptions=False)


@pytest.mark.parametrize("value, expected", [
    ("127.0.0.1:8765", ("127.0.0.1", 8765)), ("[::1]:8765", ("::1", 8765)), ("LocalHost", ("localhost", None)),
    ("[::1]", ("::1", None)), ("evil.example:80", ("evil.example", 80)), ("127.0.0.1:x", ("", None)),
], ids=["ipv4", "ipv6", "name", "ipv6-no-port", "other", "bad-port"])
def test_a_host_splits_into_its_name_and_port(value, expected):
    assert split_host(value) == expected


@pytest.mark.parametrize("address", ["127.0.0.1", "[::1]"], ids=["ipv4", "ipv6"])
def test_the_page_is_answered_at_its_address_and_at_localhost(address):
    client = client_at(address)
    assert client.get("/api/meta").status_code == 200
    assert client.post("/api/summary", json={"design": tables()}).json()["status"] == "ok"
    assert client.get("/api/meta", headers={"host": f"localhost:{PORT}"}).status_code == 200
    # the browser's own Origin on a POST from the page
    answer = client.post("/api/summary", json={"design": tables()}, headers={"origin": f"http://localhost:{PORT}"})
    assert answer.status_code == 200


@pytest.mark.parametrize("host", ["evil.example:8765", "evil.example", "127.0.0.1:8766", "localhost:8766",
                                  "10.0.0.1:8765", ""],
                         ids=["rebound-name", "no-port", "other-port", "localhost-other-port", "other-address", "none"])
def test_a_request_addressed_elsewhere_is_403(host):
    client = client_at("127.0.0.1")
    for answer in (client.get("/api/meta", headers={"host": host}),
                   client.post("/api/jobs", json={"tool": "best_pin", "design": tables()}, headers={"host": host})):
        assert answer.status_code == 403 and answer.json()["field"] == "host", answer.text
    assert not client.app.state.jobs._jobs   # nothing started


@pytest.mark.parametrize("origin", ["http://evil.example", "http://evil.example:8765", "null",
                                    "https://127.0.0.1:8765", "http://127.0.0.1:8766"])
def test_a_request_from_another_pages_origin_is_403(origin):
    answer = client_at("127.0.0.1").post("/api/summary", json={"design": tables()}, headers={"origin": origin})
    assert answer.status_code == 403 and answer.json()["field"] == "origin"


@pytest.mark.parametrize("content_type", ["text/plain", "text/plain;charset=UTF-8", "application/x-www-form-urlencoded",
                                          "multipart/form-data; boundary=x", None])
def test_a_post_that_is_not_json_is_415(content_type):
    """What a form on another page can send without asking the server first; and no type at all."""
    client = client_at("127.0.0.1")
    headers = {} if content_type is None else {"content-type": content_type}
    for path in ("/api/shot", "/api/jobs", "/api/read", "/api/jobs/1/cancel"):
        answer = client.post(path, content=json.dumps({"design": tables(), "tool": "best_pin"}), headers=headers)
        assert answer.status_code == 415 and answer.json()["field"] == "content-type", (path, answer.text)
    assert not client.app.state.jobs._jobs
    answer = client.post("/api/summary", content=json.dumps({"design": tables()}),
                         headers={"content-type": "application/json; charset=utf-8"})
    assert answer.status_code == 200


def test_a_cancelled_job_counts_until_its_thread_ends():
    """Cancel answers at once, but a tool that cannot stop between its steps runs on: it holds its
    client's place (and the server's) until its thread has returned."""
    jobs, release = Jobs(), threading.Event()
    first = jobs.start("page", "stubborn", lambda job: release.wait(30))
    assert jobs.cancel(first.id).state == "cancelled"
    with pytest.raises(TooMany, match="still stopping"):
        jobs.start("page", "again", lambda job: None)
    other = jobs.start("other page", "quick", lambda job: release.wait(30))
    with pytest.raises(TooMany, match="tools are running on this server"):
        jobs.start("third page", "quick", lambda job: None)
    release.set()
    assert first.ended.wait(10) and other.ended.wait(10)
    assert first.to_json()["state"] == "cancelled" and first.to_json()["ended"]
    jobs.start("page", "again", lambda job: None).ended.wait(10)


def test_a_cancelled_tool_stops_at_its_next_step():
    """The what-if sweep checks between its chunks of shots: cancelled, its thread ends long before the
    sweep would (201 shots of the paper's machine)."""
    client = client_at("127.0.0.1")
    slow = {"tool": "what_if", "design": tables(), "client": "c",
            "inputs": {"field": "machine.sling_length", "low": 0.3, "high": 1.2, "steps": 201}}
    job = client.post("/api/jobs", json=slow).json()
    client.post(f"/api/jobs/{job['id']}/cancel", json={})
    running = client.app.state.jobs.get(job["id"])
    assert running.ended.wait(STOP_WAIT)
    assert running.progress < 1.0 and running.result is None


@pytest.mark.parametrize("tool, inputs", [
    ("optimise", {"front": True, "problem": "around", "generations": 40}),
    ("optimise", {"front": False, "problem": "paper", "generations": 40}),
])
def test_a_cancelled_optimisation_stops_before_its_next_batch_of_shots(monkeypatch, tool, inputs):
    """The optimiser checks the job before each batch of shots (``Evaluator(check=...)``): cancelled
    mid-search, at most the batch in flight is shot, and its thread ends without a result."""
    from analytic.optimise.evaluate import Evaluator

    batches, original = [], Evaluator._fast_throws
    monkeypatch.setattr(Evaluator, "_fast_throws", lambda self, *a: batches.append(None) or original(self, *a))
    client = client_at("127.0.0.1")
    job = client.post("/api/jobs", json={"tool": tool, "design": tables(), "client": "c", "inputs": inputs}).json()
    deadline = time.monotonic() + STOP_WAIT
    while len(batches) < 3 and time.monotonic() < deadline:   # well into the global stage's generations
        time.sleep(0.01)
    assert len(batches) >= 3
    client.post(f"/api/jobs/{job['id']}/cancel", json={})
    shot_before = len(batches)
    running = client.app.state.jobs.get(job["id"])
    assert running.ended.wait(STOP_WAIT)
    assert len(batches) <= shot_before + 1
    assert running.result is None and running.to_json()["state"] == "cancelled"


def _on_the_loop() -> bool:
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return False
    return True


@pytest.mark.parametrize("path, target", [("/api/summary", "summary_json"), ("/api/shot", "shot_json"),
                                          ("/api/toml", "dumps_design"), ("/api/jobs", "design_from_dict"),
                                          ("/api/read", "design_from_dict")])
def test_no_shot_nor_design_is_built_on_the_event_loop(monkeypatch, path, target):
    """Each handler hands its work to a thread: the event loop keeps answering other requests (and a
    stop) while a shot runs."""
    seen = []
    original = getattr(workbench_app, target)

    def spy(*args, **kwargs):
        seen.append(_on_the_loop())
        return original(*args, **kwargs)

    monkeypatch.setattr(workbench_app, target, spy)
    body = {"toml": "[machine]\nsling_length = 0.5\n"} if path == "/api/read" else {"design": tables(), "tool": "aim"}
    client_at("127.0.0.1").post(path, json=body)
    assert seen == [False]


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _request(port: int, method: str, path: str, body: bytes = b"", headers: dict | None = None) -> tuple[int, dict]:
    """One request over a new connection: (status, the JSON answer)."""
    import http.client

    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    connection.request(method, path, body=body, headers={"content-type": "application/json", **(headers or {})})
    response = connection.getresponse()
    status, data = response.status, json.loads(response.read())
    connection.close()
    return status, data


def test_the_server_refuses_other_pages_and_stops_on_ctrl_c_with_one_line():
    """``python -m workbench`` as a user runs it: a foreign Host is 403 and text/plain 415 on the wire;
    then Ctrl-C while a job runs, a shot's connection stays open and another request is half sent
    ends it within ``STOP_WAIT`` with one line, no traceback, exit status 130 (the shell's for Ctrl-C)."""
    port = free_port()
    server = subprocess.Popen([sys.executable, "-m", "workbench", "--port", str(port), "--no-browser"], cwd=ROOT,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert f"http://127.0.0.1:{port}/" in server.stdout.readline()
        body = json.dumps({"design": tables()}).encode()
        assert _request(port, "POST", "/api/shot", body)[0] == 200
        assert _request(port, "POST", "/api/shot", body, {"host": f"evil.example:{port}"})[0] == 403
        assert _request(port, "POST", "/api/shot", body, {"content-type": "text/plain"})[0] == 415
        slow = {"tool": "what_if", "design": tables(), "client": "c",
                "inputs": {"field": "machine.sling_length", "low": 0.3, "high": 1.2, "steps": 201}}
        status, job = _request(port, "POST", "/api/jobs", json.dumps(slow).encode())
        assert status == 200 and job["state"] == "running"
        idle = socket.create_connection(("127.0.0.1", port))   # a page's kept-alive connection
        idle.sendall(b"GET /api/meta HTTP/1.1\r\nHost: 127.0.0.1:%d\r\n\r\n" % port)
        half = socket.create_connection(("127.0.0.1", port))   # a body that never arrives
        half.sendall(b"POST /api/shot HTTP/1.1\r\nHost: 127.0.0.1:%d\r\ncontent-type: application/json\r\n"
                     b"content-length: 1000\r\n\r\n{" % port)
        time.sleep(0.5)
        server.send_signal(signal.SIGINT)
        began = time.monotonic()
        out, err = server.communicate(timeout=STOP_WAIT)
        took = time.monotonic() - began
        idle.close()
        half.close()
    finally:
        if server.poll() is None:
            server.kill()
            server.communicate()
    assert "Traceback" not in err and "Error" not in err, err
    assert err.strip().splitlines() == ["workbench stopped"], err
    assert server.returncode == 130
    assert took < STOP_WAIT

"""The web app: the page's files and its JSON API (Starlette), every answer built by the library."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.middleware import Middleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from analytic.design import DesignError
from analytic.design_file import design_from_dict, design_to_dict, dumps_design

from workbench.applies import rules_table
from workbench.fields import fields_table, loads_table, units_table
from workbench.guard import Guard
from workbench.jobs import Jobs, TooMany
from workbench.presets import presets_json
from workbench.shot import PAGE_FLIGHT_SAMPLE_STEP, PAGE_SAMPLE_STEP, SAMPLE_STEP_BOUNDS, shot_json, summary_json
from workbench.tools import TOOLS

STATIC = Path(__file__).with_name("static")
#: Largest request body, bytes: a design is under 2 kB, an uploaded TOML file a few kB.
MAX_BODY = 64 * 1024


class BadRequest(Exception):
    """A request the API refuses: answered 400 (or ``status``) with ``{"error", "field"}``."""

    def __init__(self, message: str, field: str = "", status: int = 400):
        super().__init__(message)
        self.field, self.status = field, status


def error_response(message: str, field: str = "", status: int = 400) -> JSONResponse:
    return JSONResponse({"error": message, "field": field}, status_code=status)


async def read_body(request: Request) -> bytes:
    """The request's body, refused past ``MAX_BODY`` before more of it is read."""
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > MAX_BODY):
        raise BadRequest(f"request body larger than {MAX_BODY} bytes", "body", 413)
    body = b""
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BODY:
            raise BadRequest(f"request body larger than {MAX_BODY} bytes", "body", 413)
    return body


async def read_json(request: Request) -> dict[str, Any]:
    """The body as a JSON object."""
    try:
        data = json.loads(await read_body(request))
    except (ValueError, UnicodeDecodeError) as error:
        raise BadRequest(f"body is not JSON: {error}", "body") from None
    except RecursionError:
        raise BadRequest("body is not a design: nested too deeply", "body") from None
    if not isinstance(data, dict):
        raise BadRequest("body must be a JSON object", "body")
    return data


def design_of(data: dict[str, Any]):
    """The ``design`` of a request body, built and checked by the design contract."""
    if "design" not in data:
        raise BadRequest('missing "design": the tables of a design file as JSON objects', "design")
    tables = data["design"]
    if not isinstance(tables, dict):
        raise BadRequest('"design" must be an object: the tables of a design file', "design")
    return design_from_dict(tables, name=str(tables.get("name", "workbench")))


async def shot(request: Request) -> Response:
    """``POST /api/shot``: ``simulate --json``'s keys and ``history``; the body may set the
    history's spacings, s (``"sample_step"``, ``"flight_sample_step"``, in ``SAMPLE_STEP_BOUNDS``)."""
    data = await read_json(request)
    steps = {name: sample_step(name, data[name]) for name in SAMPLE_STEP_BOUNDS if name in data}
    return JSONResponse(await run_in_threadpool(lambda: shot_json(design_of(data), **steps)))


def sample_step(name: str, value: Any) -> float:
    """A history spacing of a shot request, s, checked against ``SAMPLE_STEP_BOUNDS``."""
    low, high = SAMPLE_STEP_BOUNDS[name]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise BadRequest(f"{name} = {value!r}: must be a number of seconds from {low:g} to {high:g}", name)
    return float(value)


async def summary(request: Request) -> Response:
    """``POST /api/summary``: the fast path's summary of the design (``simulate --json``'s keys)."""
    data = await read_json(request)
    return JSONResponse(await run_in_threadpool(lambda: summary_json(design_of(data))))


async def design_toml(request: Request) -> Response:
    """``POST /api/toml``: the design as a TOML file that ``python -m analytic simulate`` reads."""
    data = await read_json(request)
    design, text = await run_in_threadpool(lambda: _with_text(design_of(data)))
    return Response(text, media_type="application/toml",
                    headers={"content-disposition": f'attachment; filename="{_file_name(design.name)}.toml"'})


def _with_text(design):
    return design, dumps_design(design)


def _file_name(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_" else "-" for c in name)[:60] or "design"


async def read_toml(request: Request) -> Response:
    """``POST /api/read``: ``{"toml": an uploaded design file's text}`` -> its tables (file units), checked."""
    text = (await read_json(request)).get("toml")
    if not isinstance(text, str):
        raise BadRequest('missing "toml": the design file\'s text', "toml")
    return JSONResponse(await run_in_threadpool(_read_design, text))


def _read_design(text: str) -> dict[str, Any]:
    import tomllib

    try:
        tables = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise DesignError("file", "upload", f"not valid TOML: {error}") from None
    design = design_from_dict(tables, name=str(tables.get("name", "uploaded")))
    return {"design": design_to_dict(design)}


async def meta(request: Request) -> Response:
    """``GET /api/meta``: the design fields (with their defaults), the units, the history spacings the
    stage asks for, which fields apply under which choices (``workbench.applies``) and the peak loads."""
    return JSONResponse(await run_in_threadpool(meta_json))


def meta_json() -> dict[str, Any]:
    return {"groups": fields_table(), "units": units_table(),
            "sampling": {"sample_step": PAGE_SAMPLE_STEP, "flight_sample_step": PAGE_FLIGHT_SAMPLE_STEP},
            "rules": rules_table(), "loads": loads_table()}


async def presets(request: Request) -> Response:
    return JSONResponse(await run_in_threadpool(presets_json))


async def start_job(request: Request) -> Response:
    """``POST /api/jobs``: ``{"tool", "design", "inputs", "client"}`` -> the job (poll ``GET /api/jobs/ID``)."""
    data = await read_json(request)
    tool = TOOLS.get(data.get("tool"))
    if tool is None:
        raise BadRequest(f"unknown tool {data.get('tool')!r}; expected one of {', '.join(TOOLS)}", "tool")
    design = await run_in_threadpool(design_of, data)
    inputs = data.get("inputs", {})
    if not isinstance(inputs, dict):
        raise BadRequest('"inputs" must be an object', "inputs")
    client = f"{request.client.host if request.client else ''}/{str(data.get('client', ''))[:64]}"
    try:
        job = request.app.state.jobs.start(client, data["tool"], lambda job: tool(design, inputs, job))
    except TooMany as error:
        raise BadRequest(str(error), "tool", 429) from None
    return JSONResponse(job.to_json())


async def job_state(request: Request) -> Response:
    job = request.app.state.jobs.get(request.path_params["id"])
    if job is None:
        raise BadRequest("no such job", "id", 404)
    return JSONResponse(job.to_json())


async def cancel_job(request: Request) -> Response:
    job = request.app.state.jobs.cancel(request.path_params["id"])
    if job is None:
        raise BadRequest("no such job", "id", 404)
    return JSONResponse(job.to_json())


async def index(request: Request) -> Response:
    return FileResponse(STATIC / "index.html")


async def on_design_error(request: Request, error: DesignError) -> Response:
    return error_response(str(error), error.field)


async def on_bad_request(request: Request, error: BadRequest) -> Response:
    return error_response(str(error), error.field, error.status)


async def on_error(request: Request, error: Exception) -> Response:
    """Anything else: a message, never a traceback."""
    return error_response(f"the server could not answer: {type(error).__name__}", "", 500)


def build_app(hosts: tuple[str, ...] = ()) -> Starlette:
    """The workbench app: the page at ``/``, its files under ``/static``, the API under ``/api``;
    answering only requests addressed to it (``workbench.guard``: ``localhost``, the address it was
    reached at, or one of ``hosts``)."""
    app = Starlette(routes=[
        Route("/", index),
        Route("/api/meta", meta),
        Route("/api/presets", presets),
        Route("/api/shot", shot, methods=["POST"]),
        Route("/api/summary", summary, methods=["POST"]),
        Route("/api/toml", design_toml, methods=["POST"]),
        Route("/api/read", read_toml, methods=["POST"]),
        Route("/api/jobs", start_job, methods=["POST"]),
        Route("/api/jobs/{id}", job_state),
        Route("/api/jobs/{id}/cancel", cancel_job, methods=["POST"]),
        Mount("/static", StaticFiles(directory=STATIC), name="static"),
    ], exception_handlers={DesignError: on_design_error, BadRequest: on_bad_request, Exception: on_error},
        middleware=[Middleware(Guard, hosts=hosts)])
    app.state.jobs = Jobs()
    return app

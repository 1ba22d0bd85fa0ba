"""Ray executor for the sweeps: the tasks of :func:`.sweeps.stability_map` (one continuation
chain or one cold start each) on a Ray cluster, possibly spread over several machines.

    from bearing_gym.analysis.ray_backend import RayExecutor
    with RayExecutor(address="auto") as ex:            # or "ray://head:10001", or None
        rows = stability_map(base, preloads, shaft_speeds_rpm=speeds, executor=ex)

:class:`RayExecutor` has the ``concurrent.futures`` interface that :func:`.sweeps.run_tasks`
uses: ``submit(fn, *args)`` returns a :class:`concurrent.futures.Future` (through
``ObjectRef.future()``), so results come back in task order and are identical to the process
pool's (the physics is deterministic; rows travel by pickle, floats exactly).

Ray is an optional dependency (``pip install 'bearing-gym[ray]'``), imported only when an
executor is made. Every node needs the same bearing-gym install: the workers import the task
functions by name (``bearing_gym.analysis.sweeps.points.continuation_chain``), and importing the
package points numba's cache at ``$NUMBA_CACHE_DIR`` (else ``~/.cache/bearing_gym/numba``) of
the worker's node, keyed by the hash of the installed source, so each node compiles the kernels
once and then reuses them; a worker started by a local ``ray.init`` inherits this process's
environment, a worker of a cluster the environment of its ``ray start``.
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
from typing import Any, Callable

__all__ = ["RayExecutor", "require_ray", "INSTALL_HINT"]

INSTALL_HINT = "install with pip install 'bearing-gym[ray]'"


def require_ray():
    """The ``ray`` module, or ImportError saying how to install it."""
    try:
        import ray
    except ImportError as err:
        raise ImportError(f"the Ray backend needs the ray package ({err}); {INSTALL_HINT}") from None
    return ray


class RayExecutor:
    """``concurrent.futures``-style executor running each task as a Ray task (1 CPU each).

    ``address``: the cluster to connect to: ``"auto"`` (``$RAY_ADDRESS`` if set, else the
    cluster this node joined with ``ray start``), ``"HOST:6379"``, or ``"ray://HOST:10001"``
    (Ray Client, from outside the cluster); ``None``: a new local Ray instance with
    ``num_cpus`` CPUs (default: all), stopped again by :meth:`shutdown`. If Ray is already
    initialised in this process (e.g. by the caller's own ``ray.init``) that session is used
    and the arguments are ignored.

    :meth:`shutdown` disconnects only a session this executor opened (and stops the local
    instance only if it started it); a cluster it merely connected to keeps running, and a
    session the caller opened stays open.
    """

    def __init__(self, address: str | None = None, num_cpus: int | None = None,
                 **init_kwargs: Any):
        ray = require_ray()
        self._ray = ray
        self._owns_session = False
        if not ray.is_initialized():
            kw: dict[str, Any] = {}
            if address is None:               # a private local instance ("local": not the
                address = "local"             # cluster of $RAY_ADDRESS or of a `ray start`)
                kw.update(include_dashboard=False, num_cpus=num_cpus)
            if not str(address).startswith("ray://"):   # Ray Client forwards these to the server
                kw.update(log_to_driver=False, logging_level=logging.WARNING)
            kw.update(init_kwargs)
            ray.init(address=address, **kw)
            self._owns_session = True
        self._remote: dict[Callable, Any] = {}

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> cf.Future:
        remote = self._remote.get(fn)
        if remote is None:
            remote = self._remote[fn] = self._ray.remote(fn)
        return remote.remote(*args, **kwargs).future()

    def shutdown(self, wait: bool = True) -> None:
        """Disconnect (and stop a local instance) only if this executor called ``ray.init``."""
        if self._owns_session and self._ray.is_initialized():
            self._ray.shutdown()
        self._owns_session = False

    def __enter__(self) -> "RayExecutor":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.shutdown()

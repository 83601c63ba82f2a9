"""``trical serve``: the API and the pages on the desktop's listener (HTTP, or TLS with ``--https``), and the
phone's door: HTTPS on every interface for the phone that scans the start page's code (app.reach.phone_door)."""

from __future__ import annotations

import contextlib
import socket
from typing import TYPE_CHECKING

from app import __version__

if TYPE_CHECKING:
    from collections.abc import Callable
    from pathlib import Path

    from app.config import Settings
    from app.reach.phone_door import PhoneDoor


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical serve``: uvicorn on ``--host``/``--port`` (HTTP, or TLS with ``--https`` or ``--cert`` and
    ``--key``), and beside it on the same application the phone's door at ``--phone-port`` unless it is 0 or a
    TRICAL_PUBLIC_URL gives the phones' address."""
    import asyncio

    from app.reach import tls

    config = settings()
    if bool(args.cert) != bool(args.key):
        raise tls.CertificateError("--cert and --key go together: give both, or neither for a self-signed certificate")
    port = args.port or config.port
    host = args.host or config.host or "127.0.0.1"
    phone_port = config.phone_port if args.phone_port is None else args.phone_port
    desktop_tls = bool(args.https or args.cert)
    door_wanted = phone_port > 0 and not config.public_url
    scheme = "https" if desktop_tls else "http"
    print(f"trical {__version__} on {scheme}://{tls.url_host(host)}:{port}  (database {config.database_label})")
    tls_files = _certificate(args, config, host) if desktop_tls or door_wanted else None
    from app.main import create_app  # the whole application: imported once the options are known to be good

    app = create_app(config)
    app.state.listens_on = host
    listeners = [_listener(app, host, port, tls_files if desktop_tls else None)]
    door_socket = _door_socket(phone_port) if door_wanted else None
    if door_socket is not None and tls_files is not None:
        door = app.state.phone_door = _door(tls_files[0], phone_port, scheme, host, port)
        listeners.append(_door_listener(app, door, door_socket, tls_files))
    with contextlib.suppress(KeyboardInterrupt):  # Ctrl-C: the listeners closed, nothing to add
        asyncio.run(_serve(listeners))
    return 0


def _certificate(args, config: Settings, host: str) -> tuple[Path, Path]:
    """The given certificate files, checked, or trical's self-signed certificate for this machine's names."""
    from app.reach import tls

    if args.cert:
        tls.check_certificate_files(args.cert, args.key)
        print(f"certificate {args.cert} (SHA-256 {tls.fingerprint(args.cert)})")
        return args.cert, args.key
    hosts = tls.certificate_hosts([] if host in (*tls.EVERY_INTERFACE, "127.0.0.1") else [host])
    cert, key, made = tls.self_signed_certificate(config.tls_dir, hosts)
    print(f"{'made a' if made else 'reusing the'} self-signed certificate {cert} for {', '.join(hosts)}")
    print(f"  SHA-256 {tls.fingerprint(cert)} (a browser warns that it signed itself: proceed when it shows this)")
    return cert, key


def _door_socket(phone_port: int) -> socket.socket | None:
    """The phone's door's socket on every interface, or None (said, with what to do) when the port is taken."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind(("0.0.0.0", phone_port))
    except OSError as exc:
        sock.close()
        print(
            f"no phone's door: port {phone_port} cannot be opened ({exc.strerror}); "
            "start again with a free --phone-port (TRICAL_PHONE_PORT) for a phone to measure"
        )
        return None
    sock.listen(128)
    return sock


def _door(cert: Path, phone_port: int, scheme: str, host: str, port: int) -> PhoneDoor:
    from app.reach import tls
    from app.reach.phone_door import PhoneDoor

    # A link the phone sends to "my computer" opens on the desktop's listener: its own address, or, on
    # every interface, this machine's LAN address (another computer may open it then).
    lan = tls.lan_addresses()[0]
    desktop_host = lan if host in tls.EVERY_INTERFACE else tls.url_host(host)
    door = PhoneDoor(
        port=phone_port, desktop_origin=f"{scheme}://{desktop_host}:{port}", fingerprint=tls.fingerprint(cert)
    )
    print(
        f"phone's door on {door.origin(lan)} (every interface): only for the phone that scans the QR code of the "
        f"start page, {scheme}://{tls.url_host(host)}:{port}/"
    )
    return door


def _listener(app, host: str, port: int, tls_files: tuple | None):
    import uvicorn

    cert, key = (str(tls_files[0]), str(tls_files[1])) if tls_files else (None, None)
    config = uvicorn.Config(app, host=host, port=port, log_level="info", ssl_certfile=cert, ssl_keyfile=key)
    return uvicorn.Server(config), None


def _door_listener(app, door: PhoneDoor, sock: socket.socket, tls_files: tuple):
    import uvicorn

    from app.reach.phone_door import through

    class Door(uvicorn.Server):
        @contextlib.contextmanager
        def capture_signals(self):  # the desktop's listener takes the signals; the door ends with the process
            yield

    config = uvicorn.Config(
        through(app, door),
        lifespan="off",  # one lifespan: the desktop listener's
        log_level="info",
        ssl_certfile=str(tls_files[0]),
        ssl_keyfile=str(tls_files[1]),
    )
    return Door(config), [sock]


async def _serve(listeners) -> None:
    """Every listener on one event loop; the first (the desktop's) takes the signals, and when it ends the door
    ends with it."""
    import asyncio

    (main, _), *others = listeners
    tasks = [asyncio.create_task(server.serve(sockets=sockets)) for server, sockets in others]
    try:
        await main.serve()
    finally:
        for server, _ in others:
            server.should_exit = True
        await asyncio.gather(*tasks, return_exceptions=True)

#!/usr/bin/env python3
"""A fault-injecting HTTP proxy on loopback, in front of the local OGC stack (docs/services.md).

    fault_proxy.py PORT UPSTREAM LOG

A request for /<fault>/<rest> is forwarded to UPSTREAM/<rest> and its answer spoilt as <fault>
says; a fault named <fault>-data spoils only the data requests (GetFeature, GetCoverage, GetMap,
OGC API /items, IIIF image requests .../default.jpg) and passes the service descriptions through, so that the service opens and fails
later, part-way. Faults:

    ok          passed through
    404, 500, 503   that status, with a short text body
    slow        the answer after HV_FAULT_SLOW_S seconds (default 8: past the client's time-out)
    throttled   the answer at HV_FAULT_RATE bytes per second (default 16384), in 1 KiB pieces: a
                slow link, on which a large answer takes longer than a small one
    reset       the connection reset (RST) without an answer
    truncated   the status line and headers, a Content-Length of the whole, then half the body
    malformed   the body replaced by a broken document of the same kind (XML, JSON) with a
                correct Content-Length
    404-wide    404 for IIIF image requests wider than HV_FAULT_WIDTH pixels (default 256, the
                preview's box, hv/io/iiif.h), the rest passed through: a photograph's preview
                arrives and its full image fails; its info.json's id is made to point through the
                proxy (below)

Links to UPSTREAM in the answers (OGC API "next" and "items", the capabilities' online resources)
are rewritten to go through the proxy with the same fault. Each request is logged to LOG as one line: "<fault> <method> <path>". Listens on 127.0.0.1 only.
"""
import http.client
import http.server
import os
import re
import socket
import struct
import sys
import threading
import time
import urllib.parse

PORT, UPSTREAM, LOG = int(sys.argv[1]), sys.argv[2].rstrip("/"), sys.argv[3]
UP_HOST, UP_PORT = UPSTREAM.split("//", 1)[1].split(":")
UP_PORT = int(UP_PORT)
SLOW_S = float(os.environ.get("HV_FAULT_SLOW_S", "8"))
RATE = float(os.environ.get("HV_FAULT_RATE", "16384"))
WIDTH = int(os.environ.get("HV_FAULT_WIDTH", "256"))
FAULTS = {"ok", "404", "500", "503", "slow", "reset", "truncated", "malformed", "throttled", "404-wide"}
log_lock = threading.Lock()


def is_data(path):
    p = path.lower()
    return any(k in p for k in ("getfeature", "getcoverage", "getmap", "/items", "/default."))


def broken(body, content_type):
    text = body.decode("utf-8", "replace")
    if "json" in content_type or text.lstrip().startswith("{"):
        return b'{"type": "FeatureCollection", "features": [{"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[651000.0, 6862000.0], [,,]]] oops'
    if "xml" in content_type or text.lstrip().startswith("<"):
        return b'<?xml version="1.0"?><wfs:FeatureCollection xmlns:wfs="http://www.opengis.net/wfs/2.0"><wfs:member><broken attr="x></wfs:FeatureCollection'
    return b"\x00\x01 not what was asked for"


class Proxy(http.server.BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"

    def log_message(self, *args):
        pass

    def reply(self, status, body, content_type="text/plain", length=None, rate=None):
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body) if length is None else length))
        self.send_header("Access-Control-Allow-Origin", "*")
        self.send_header("Connection", "close")
        self.end_headers()
        if rate:
            for i in range(0, len(body), 1024):
                self.wfile.write(body[i:i + 1024])
                self.wfile.flush()
                time.sleep(len(body[i:i + 1024]) / rate)
        else:
            self.wfile.write(body)
        self.wfile.flush()
        self.close_connection = True

    def do_GET(self):
        parts = self.path.split("/", 2)
        fault, rest = (parts[1], "/" + parts[2]) if len(parts) == 3 else ("", "/")
        data_only = fault.endswith("-data")
        base = fault[: -len("-data")] if data_only else fault
        with log_lock, open(LOG, "a") as f:
            f.write(f"{fault} GET {rest}\n")
        if base not in FAULTS:
            return self.reply(400, f"unknown fault '{fault}'\n".encode())
        if data_only and not is_data(rest):
            base = "ok"
        if base == "404-wide":
            # A IIIF size "w," or "w,h" (Image API 2; "!w,h" and "pct:" are not asked for by histoview).
            m = re.search(r"/full/!?(\d+),", urllib.parse.unquote(rest))
            if m and int(m.group(1)) > WIDTH:
                return self.reply(404, f"injected 404 for an image wider than {WIDTH} px: {rest}\n".encode())
        if base in ("404", "500", "503"):
            return self.reply(int(base), f"injected {base} for {rest}\n".encode())
        if base == "reset":
            # SO_LINGER with a zero time-out: close() sends RST instead of FIN.
            self.connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            self.close_connection = True
            return
        if base == "slow":
            time.sleep(SLOW_S)
        up = http.client.HTTPConnection(UP_HOST, UP_PORT, timeout=60)
        try:
            # The client's headers go on (OGC API servers choose JSON or HTML by Accept).
            headers = {k: v for k, v in self.headers.items() if k.lower() not in ("host", "connection")}
            headers["Host"] = f"{UP_HOST}:{UP_PORT}"
            up.request("GET", rest, headers=headers)
            r = up.getresponse()
            body = r.read()
            status, ctype = r.status, r.getheader("Content-Type", "application/octet-stream")
        finally:
            up.close()
        # Links in the answer (OGC API "items" and "next", capabilities' online resources) point
        # at the stack: made to point back through the proxy, with the same fault.
        if ctype.startswith(("application/json", "application/geo+json", "text/xml", "application/xml",
                             "application/gml+xml", "text/html")) or (base == "404-wide" and "json" in ctype):
            body = body.replace(f"http://{UP_HOST}:{UP_PORT}/".encode(),
                                f"http://127.0.0.1:{PORT}/{fault}/".encode())
        if base == "truncated":
            return self.reply(status, body[: len(body) // 2], ctype, length=len(body))
        if base == "malformed":
            return self.reply(status, broken(body, ctype), ctype)
        if base == "throttled":
            return self.reply(status, body, ctype, rate=RATE)
        return self.reply(status, body, ctype)


class Server(http.server.ThreadingHTTPServer):
    daemon_threads = True
    allow_reuse_address = True


if __name__ == "__main__":
    srv = Server(("127.0.0.1", PORT), Proxy)
    print(f"fault proxy on 127.0.0.1:{PORT} -> {UPSTREAM}", flush=True)
    srv.serve_forever()

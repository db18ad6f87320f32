#!/usr/bin/env python3
"""Serves a ccache directory, read-only, as ccache's HTTP remote storage.

`docker build` (the classic builder of Debian's Docker 20.10) mounts nothing
from the host into a build, so the image's compile cannot use the host's
ccache the way `podman build -v DIR:/ccache` does. It can reach the host over
the build's network, though, and ccache 4.7 can read a remote storage over
HTTP: docker/test-image.sh starts this server on the Docker bridge's address
and passes its URL as the build argument CCACHE_REMOTE_STORAGE.

    ccache-http.py CACHE_DIR ADDRESS PORT_FILE

Listens on ADDRESS at a free port, which it writes to PORT_FILE once it is
listening. Answers GET and HEAD for /KK/REST (ccache's `subdirs` layout) with
the local entry of key KKREST (a result or a manifest: the key says which,
and the bytes are the same in local and remote storage), and 404 for any
other path; it never writes.
"""
import http.server
import os
import re
import sys

# ccache 4.7's keys: four base16 digits, then base32hex digits.
KEY = re.compile(r"^/([0-9a-f]{2})/([0-9a-v]{20,})$")


def local_path(cache_dir, key):
    # The local layout: one directory level per leading character of the
    # key (two, three or four levels, deeper as the cache grows), then the
    # rest of the key with R (result) or M (manifest) after it.
    for levels in (2, 3, 4):
        base = os.path.join(cache_dir, *key[:levels], key[levels:])
        for suffix in ("R", "M"):
            if os.path.isfile(base + suffix):
                return base + suffix
    return None


class Handler(http.server.BaseHTTPRequestHandler):
    def entry(self):
        match = KEY.match(self.path)
        path = match and local_path(self.server.cache_dir, match.group(1) + match.group(2))
        if not path:
            self.send_error(404)
            return None
        with open(path, "rb") as f:
            data = f.read()
        self.send_response(200)
        self.send_header("Content-Type", "application/octet-stream")
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        return data

    def do_GET(self):
        data = self.entry()
        if data is not None:
            self.wfile.write(data)

    def do_HEAD(self):
        self.entry()

    def log_message(self, format, *args):
        pass  # one line per compile would only hide the build's own output


def main():
    cache_dir, address, port_file = sys.argv[1:4]
    server = http.server.ThreadingHTTPServer((address, 0), Handler)
    server.cache_dir = cache_dir
    with open(port_file + ".tmp", "w") as f:
        f.write(f"{server.server_address[1]}\n")
    os.rename(port_file + ".tmp", port_file)
    server.serve_forever()


if __name__ == "__main__":
    main()

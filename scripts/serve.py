"""Serves a folder with the types a wasm page needs: on 127.0.0.1, or with --lan on
every interface, for the machines of a local network (a classroom with no hosting).

Usage: python3 scripts/serve.py FOLDER [PORT] [--lan]   (PORT 0: any free port)
Prints the address on its first line of output (with --lan, a line for each of the
machine's IPv4 addresses after it), then serves until stopped.
"""
import fcntl
import functools
import http.server
import socket
import struct
import sys


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {
        **http.server.SimpleHTTPRequestHandler.extensions_map,
        ".wasm": "application/wasm",
        ".js": "text/javascript",
    }

    def log_message(self, format, *args):
        pass


def local_addresses():
    """The machine's IPv4 addresses, one per interface that has one, read from the
    kernel (SIOCGIFADDR); nothing is sent anywhere."""
    found = []
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        for _, name in socket.if_nameindex():
            request = struct.pack("256s", name.encode()[:15])
            try:
                reply = fcntl.ioctl(probe.fileno(), 0x8915, request)  # SIOCGIFADDR
            except OSError:
                continue  # no IPv4 address on this interface
            found.append((name, socket.inet_ntoa(reply[20:24])))
    return found


def main():
    args = [a for a in sys.argv[1:] if a != "--lan"]
    lan = "--lan" in sys.argv[1:]
    if not args or len(args) > 2:
        print("usage: python3 scripts/serve.py FOLDER [PORT] [--lan]", file=sys.stderr)
        sys.exit(2)
    folder = args[0]
    port = int(args[1]) if len(args) > 1 else 8000
    handler = functools.partial(Handler, directory=folder)
    host = "0.0.0.0" if lan else "127.0.0.1"
    with http.server.ThreadingHTTPServer((host, port), handler) as server:
        port = server.server_address[1]
        print(f"serving {folder} at http://127.0.0.1:{port}/", flush=True)
        if lan:
            print(f"on every interface (port {port}); open one of these on the other machines:", flush=True)
            for name, address in local_addresses():
                if not address.startswith("127."):
                    print(f"  http://{address}:{port}/   ({name})", flush=True)
        server.serve_forever()


if __name__ == "__main__":
    main()

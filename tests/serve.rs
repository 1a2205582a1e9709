//! `bash scripts/web.sh serve [--lan]` (scripts/serve.py): the page served on this
//! machine only, or with `--lan` on every interface for a classroom's machines. Checked
//! without sending anything off the machine: the page is fetched over loopback, and
//! where the socket listens is read from the kernel's table (/proc/net/tcp).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

/// The kernel's listening TCP sockets on `port`, as their local addresses in
/// /proc/net/tcp's hex (`0100007F` is 127.0.0.1, `00000000` every interface).
///
/// The kernel writes that table in pages while other sockets come and go, so on a busy
/// machine one socket can be listed twice (CI saw `["0100007F", "0100007F"]`); a socket is
/// counted once, by its inode (the table's tenth field).
fn listening_on(port: u16) -> Vec<String> {
    let table = std::fs::read_to_string("/proc/net/tcp").unwrap();
    let mut sockets: Vec<(String, String)> = table
        .lines()
        .skip(1)
        .filter_map(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let (address, local_port) = fields.get(1)?.split_once(':')?;
            let inode = fields.get(9)?;
            // State 0A is LISTEN.
            (u16::from_str_radix(local_port, 16).ok()? == port && fields.get(3) == Some(&"0A"))
                .then(|| (inode.to_string(), address.to_string()))
        })
        .collect();
    sockets.sort();
    sockets.dedup();
    sockets.into_iter().map(|(_, address)| address).collect()
}

fn serve(lan: bool) {
    let dir = std::env::temp_dir().join(format!("particle-lab-serve-{lan}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("index.html"), "<p>the lab</p>").unwrap();
    let mut command = Command::new("python3");
    command.arg(concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/serve.py")).arg(&dir).arg("0");
    if lan {
        command.arg("--lan");
    }
    let mut child = command.stdout(Stdio::piped()).spawn().expect("python3 runs");
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut first = String::new();
    out.read_line(&mut first).unwrap();
    // "serving DIR at http://127.0.0.1:PORT/"
    let port: u16 = first.trim().trim_end_matches('/').rsplit(':').next().unwrap().parse().expect(&first);
    let listening = listening_on(port);
    if lan {
        let mut second = String::new();
        out.read_line(&mut second).unwrap();
        assert!(second.contains("on every interface"), "{second}");
        assert_eq!(listening, ["00000000"], "bound to every interface");
    } else {
        assert_eq!(listening, ["0100007F"], "bound to 127.0.0.1 only");
    }
    // The page itself, over loopback.
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.write_all(b"GET /index.html HTTP/1.0\r\nHost: localhost\r\n\r\n").unwrap();
    let mut reply = String::new();
    stream.read_to_string(&mut reply).unwrap();
    assert!(reply.starts_with("HTTP/1.0 200") && reply.ends_with("<p>the lab</p>"), "{reply}");
    let _ = child.kill();
    let _ = child.wait();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn serve_listens_on_this_machine_only() {
    serve(false);
}

#[test]
fn serve_lan_listens_on_every_interface_and_says_where() {
    serve(true);
}

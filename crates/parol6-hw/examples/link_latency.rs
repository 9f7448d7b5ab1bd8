//! Measurement tool (issue 32): where does the fake robot's round trip go under load?
//!
//! `pingpong pty|sock SECONDS`: a host thread writes a 56-byte frame every 10 ms, an echo
//! thread answers each with 60 bytes; both ask for SCHED_FIFO. Prints the distribution of
//! host write → echo read and echo write → host read.
//! `session pty|sock SECONDS`: the real session against the emulator on a pty or on its local
//! socket; prints the link losses, the status age at each publication and the period jitter.
//!
//! Run it with the host loaded, e.g. 8 × `sh -c 'while :; do :; done'` on 2 cores:
//! `cargo run --release -p parol6-hw --example link_latency -- session pty 150`.

use std::io::{Read, Write};
use std::time::{Duration, Instant};

fn pct(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn report(name: &str, mut v: Vec<f64>) {
    let over = |t: f64| v.iter().filter(|x| **x > t).count();
    let (o10, o30, o60) = (over(10.0), over(30.0), over(60.0));
    let n = v.len();
    let p50 = pct(&mut v, 0.5);
    let p99 = pct(&mut v, 0.99);
    let p999 = pct(&mut v, 0.999);
    let max = v.last().copied().unwrap_or(0.0);
    println!(
        "{name}: n={n} p50={p50:.3}ms p99={p99:.3}ms p99.9={p999:.3}ms max={max:.3}ms >10ms={o10} >30ms={o30} >60ms={o60}"
    );
}

type Res = Result<(), Box<dyn std::error::Error>>;

fn pingpong<H, E>(mut host: H, mut echo: E, seconds: f64) -> Res
where
    H: Read + Write + Send + 'static,
    E: Read + Write + Send + 'static,
{
    let (tx, rx) = std::sync::mpsc::channel::<(Instant, Instant)>();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let st = stop.clone();
    let echo_t = std::thread::spawn(move || {
        parol6_hw::priority::raise_current_thread();
        let mut buf = [0u8; 56];
        let reply = [0x55u8; 60];
        while !st.load(std::sync::atomic::Ordering::Relaxed) {
            if echo.read_exact(&mut buf).is_err() {
                continue;
            }
            let got = Instant::now();
            if echo.write_all(&reply).is_err() {
                break;
            }
            let sent = Instant::now();
            if tx.send((got, sent)).is_err() {
                break;
            }
        }
    });
    parol6_hw::priority::raise_current_thread();
    let frame = [0xAAu8; 56];
    let mut rbuf = [0u8; 60];
    let mut fwd = Vec::new();
    let mut back = Vec::new();
    let mut rtt = Vec::new();
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    let mut next = Instant::now();
    while Instant::now() < end {
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        }
        next += Duration::from_millis(10);
        let w = Instant::now();
        host.write_all(&frame)?;
        host.read_exact(&mut rbuf)?;
        let r = Instant::now();
        let (got, sent) = rx.recv()?;
        fwd.push(got.duration_since(w).as_secs_f64() * 1e3);
        back.push(r.duration_since(sent).as_secs_f64() * 1e3);
        rtt.push(r.duration_since(w).as_secs_f64() * 1e3);
        if next < Instant::now() {
            next = Instant::now();
        }
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    drop(host);
    if echo_t.join().is_err() {
        return Err("the echo thread panicked".into());
    }
    report("host write -> echo read ", fwd);
    report("echo write -> host read ", back);
    report("round trip              ", rtt);
    Ok(())
}

fn main() -> Res {
    let args: Vec<String> = std::env::args().collect();
    let secs: f64 = args.get(3).or(args.get(2)).and_then(|s| s.parse().ok()).unwrap_or(30.0);
    match args.get(1).map(String::as_str) {
        Some("pingpong") => match args.get(2).map(String::as_str) {
            Some("pty") => {
                let (mut master, slave) = serialport::TTYPort::pair()?;
                let path = serialport::SerialPort::name(&slave).ok_or("the pty has no path")?;
                let mut host = parol6_hw::ports::open_port(&path)?;
                host.set_timeout(Duration::from_secs(2))?;
                serialport::SerialPort::set_timeout(&mut master, Duration::from_secs(2))?;
                pingpong(host, master, secs)?;
                drop(slave);
            }
            Some("sock") => {
                let (a, b) = std::os::unix::net::UnixStream::pair()?;
                pingpong(a, b, secs)?;
            }
            _ => eprintln!("pingpong pty|sock SECONDS"),
        },
        Some("session") => {
            let cfg = parol6_hw::emulator::EmulatorConfig {
                log_commands: false,
                ..parol6_hw::emulator::EmulatorConfig::homed_at_standby()
            };
            let emu = if args.get(2).map(String::as_str) == Some("sock") {
                parol6_hw::emulator::EmulatorHandle::spawn_socket(cfg)
            } else {
                parol6_hw::emulator::EmulatorHandle::spawn(cfg)
            }?;
            println!("port {}", emu.path());
            let s = parol6_hw::session::Session::open(emu.path(), parol6_hw::session::SessionConfig::default())?;
            s.wait_connected(Duration::from_secs(5))?;
            let t0 = Instant::now();
            let end = t0 + Duration::from_secs_f64(secs);
            let mut last = 0;
            // the status age at each publication (once per tick), sampled by a FIFO thread
            parol6_hw::priority::raise_current_thread();
            let mut ages = Vec::new();
            let mut seen = None;
            while Instant::now() < end {
                std::thread::sleep(Duration::from_millis(2));
                let snap = s.snapshot();
                if seen != Some(snap.published_at) {
                    seen = Some(snap.published_at);
                    if let Some(at) = snap.last_status_at {
                        ages.push(snap.published_at.saturating_duration_since(at).as_secs_f64() * 1e3);
                    }
                }
                if snap.link_losses != last {
                    last = snap.link_losses;
                    println!("t={:.1}s loss #{last}: {:?}", t0.elapsed().as_secs_f64(), snap.fault);
                }
            }
            report("status age at publish   ", ages);
            let snap = s.snapshot();
            println!(
                "session {secs:.0} s: link_losses={} per_min={:.2} frames_sent={} jitter_p99_ms={:.3} (last {} periods)",
                snap.link_losses,
                snap.link_losses as f64 * 60.0 / secs,
                snap.frames_sent,
                snap.period_jitter_p99_ms,
                parol6_hw::session::TIMING_WINDOW
            );
        }
        _ => eprintln!("usage: link_latency pingpong pty|sock SECONDS | session pty|sock SECONDS"),
    }
    Ok(())
}

//! Finds QEMU and the `pil` firmware image, starts QEMU, and connects.
use super::link::PilLink;
use anyhow::{bail, Context, Result};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// `qemu-system-arm` from `$MRE_QEMU` or the PATH.
pub fn qemu_binary() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("MRE_QEMU") {
        return Some(PathBuf::from(p));
    }
    std::env::var_os("PATH")?
        .to_str()?
        .split(':')
        .map(|dir| Path::new(dir).join("qemu-system-arm"))
        .find(|p| p.is_file())
}

/// A `qemu-system-arm` that has the board's machine, or why there is none:
/// an older QEMU (bookworm's 7.2) lacks `b-l475e-iot01a` and would fail the
/// run with "unsupported machine type".
pub fn usable_qemu() -> Result<PathBuf, String> {
    let qemu = qemu_binary().ok_or_else(|| format!("qemu-system-arm was not found: {INSTALL_HINT}"))?;
    with_board_machine(qemu)
}

/// `qemu` if it lists the board's machine, else why it cannot run the PIL image.
fn with_board_machine(qemu: PathBuf) -> Result<PathBuf, String> {
    let machines = Command::new(&qemu)
        .args(["-machine", "help"])
        .output()
        .map_err(|e| format!("{} does not run ({e}): {INSTALL_HINT}", qemu.display()))?;
    if String::from_utf8_lossy(&machines.stdout).contains(MACHINE) {
        Ok(qemu)
    } else {
        Err(format!(
            "{} has no {MACHINE} machine (it is older than QEMU 10): {INSTALL_HINT}",
            qemu.display()
        ))
    }
}

/// The QEMU machine the PIL image runs on.
pub const MACHINE: &str = "b-l475e-iot01a";

/// Why the firmware images cannot be built here, if they cannot: the
/// `thumbv7em-none-eabihf` standard library is not installed.
pub fn firmware_target_missing() -> Option<String> {
    let sysroot = Command::new(std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into()))
        .args(["--print", "sysroot"])
        .output()
        .ok()?;
    let sysroot = String::from_utf8_lossy(&sysroot.stdout).trim().to_string();
    let lib = Path::new(&sysroot).join("lib/rustlib/thumbv7em-none-eabihf");
    (!lib.is_dir())
        .then(|| "the board's Rust target is not installed: rustup target add thumbv7em-none-eabihf".to_string())
}

/// How to install QEMU 10 (the `b-l475e-iot01a` machine is not in bookworm's 7.2).
pub const INSTALL_HINT: &str = "install qemu-system-arm ≥ 10 (Debian bookworm: \
    apt-get install -y -t \"$(.ci/apt-backports)\" qemu-system-arm, which adds bookworm-backports \
    from the mirror your apt sources already use)";

/// The workspace root (this crate's parent directory).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// Builds the PIL image (`cargo fw-pil`). Returns its path
/// (`target/images/fw-pil/mre-firmware`; crate::cargo_build).
pub fn build_firmware() -> Result<PathBuf> {
    crate::cargo_build::firmware_image(&workspace_root(), "fw-pil")
}

/// Builds the PIL image with the boards' RTT logger, its buffer full and
/// block-if-full (`cargo fw-pil-rtt`). Returns its path.
pub fn build_firmware_rtt() -> Result<PathBuf> {
    crate::cargo_build::firmware_image(&workspace_root(), "fw-pil-rtt")
}

/// The address of the firmware's symbol `name` (a `#[no_mangle]` static),
/// from the image's ELF symbol table.
pub fn symbol_address(elf: &Path, name: &str) -> Result<u32> {
    use object::{Object, ObjectSymbol};
    let bytes = std::fs::read(elf).with_context(|| format!("reading {}", elf.display()))?;
    let file = object::File::parse(&*bytes).with_context(|| format!("{} is not an ELF image", elf.display()))?;
    let symbol = file
        .symbols()
        .find(|s| s.name() == Ok(name))
        .with_context(|| format!("the firmware image {} has no symbol {name}", elf.display()))?;
    u32::try_from(symbol.address()).with_context(|| format!("{name} lies outside the 32-bit address space"))
}

/// A running QEMU with the firmware; killed on drop.
pub struct Qemu {
    child: Child,
    /// QEMU's human monitor on a local TCP socket (register reads in tests).
    monitor_port: u16,
    /// Holds the pty's symlink ([`Qemu::start_on_pty`]).
    _pty_dir: Option<tempfile::TempDir>,
    /// QEMU's stderr, for the error message when it exits early.
    errors: std::fs::File,
}

impl Qemu {
    /// Starts `elf` on the `b-l475e-iot01a` machine with USART1 on a local
    /// TCP socket and connects to it. defmt (semihosting) output goes to
    /// `log` (binary defmt frames; decode with `defmt-print -e ELF`).
    pub fn start(qemu: &Path, elf: &Path, log: Option<&Path>) -> Result<(Qemu, PilLink)> {
        // Ask the OS for a free port; QEMU binds it right after.
        let port = TcpListener::bind("127.0.0.1:0")?.local_addr()?.port();
        let chardev = format!("socket,id=u1,host=127.0.0.1,port={port},server=on,wait=on,nodelay=on");
        let mut qemu = Self::spawn(qemu, elf, log, &chardev, None)?;
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            match TcpStream::connect(("127.0.0.1", port)) {
                Ok(stream) => return Ok((qemu, PilLink::new(stream)?)),
                Err(e) => {
                    qemu.check_running()?;
                    if Instant::now() > deadline {
                        bail!("cannot connect to QEMU's USART1 socket on port {port}: {e}");
                    }
                    std::thread::sleep(Duration::from_millis(50));
                }
            }
        }
    }

    /// Starts `elf` with USART1 on a pseudo-terminal, as a real board's
    /// serial port would be, and returns its path (a symlink to the pty) for
    /// `mre pil --serial` and `mre upload --port`. The firmware boots at
    /// once: its boot hello is lost, as with a board that is already running.
    pub fn start_on_pty(qemu: &Path, elf: &Path, log: Option<&Path>) -> Result<(Qemu, PathBuf)> {
        let dir = tempfile::tempdir().context("temporary folder for the pty link")?;
        let pty = dir.path().join("usart1");
        let chardev = format!("pty,id=u1,path={}", pty.display());
        let mut qemu = Self::spawn(qemu, elf, log, &chardev, Some(dir))?;
        let deadline = Instant::now() + Duration::from_secs(20);
        while !pty.exists() {
            qemu.check_running()?;
            if Instant::now() > deadline {
                bail!("QEMU did not create its pty {}", pty.display());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok((qemu, pty))
    }

    fn spawn(
        qemu: &Path,
        elf: &Path,
        log: Option<&Path>,
        chardev: &str,
        pty_dir: Option<tempfile::TempDir>,
    ) -> Result<Qemu> {
        if !elf.is_file() {
            bail!(
                "firmware image {} not found: build it with `cargo fw-pil`",
                elf.display()
            );
        }
        let monitor_port = TcpListener::bind("127.0.0.1:0")?.local_addr()?.port();
        let stdout = match log {
            Some(p) => Stdio::from(std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?),
            None => Stdio::null(),
        };
        // stderr to a file, not a pipe: an undrained pipe could stall QEMU.
        let errors = tempfile::tempfile().context("temporary file for QEMU's stderr")?;
        let child = Command::new(qemu)
            .args(["-M", "b-l475e-iot01a", "-nographic", "-monitor"])
            .arg(format!("tcp:127.0.0.1:{monitor_port},server=on,wait=off"))
            .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
            .arg(elf)
            .arg("-chardev")
            .arg(chardev)
            .args(["-serial", "chardev:u1"])
            .stdin(Stdio::null())
            .stdout(stdout)
            .stderr(Stdio::from(errors.try_clone()?))
            .spawn()
            .with_context(|| format!("starting {}", qemu.display()))?;
        Ok(Qemu {
            child,
            monitor_port,
            _pty_dir: pty_dir,
            errors,
        })
    }

    /// Fails with QEMU's stderr if it has exited.
    fn check_running(&mut self) -> Result<()> {
        if let Some(status) = self.child.try_wait()? {
            use std::io::{Read, Seek};
            let mut err = String::new();
            self.errors.rewind().ok();
            self.errors.read_to_string(&mut err).ok();
            bail!("QEMU exited ({status}) before the link came up: {err}");
        }
        Ok(())
    }

    /// Reads a 32-bit word of the emulated chip's physical address space
    /// (a peripheral register, too) through QEMU's monitor (`xp`).
    pub fn read_word(&self, address: u32) -> Result<u32> {
        use std::io::{Read, Write};
        let mut monitor =
            TcpStream::connect(("127.0.0.1", self.monitor_port)).context("connecting to QEMU's monitor")?;
        monitor.set_read_timeout(Some(Duration::from_secs(10)))?;
        let mut text = Vec::new();
        let read_until_prompt = |monitor: &mut TcpStream, text: &mut Vec<u8>| -> Result<()> {
            let mut buf = [0u8; 512];
            while !String::from_utf8_lossy(text).trim_end().ends_with("(qemu)") {
                let n = monitor.read(&mut buf).context("reading QEMU's monitor")?;
                if n == 0 {
                    bail!("QEMU's monitor closed");
                }
                text.extend_from_slice(buf.get(..n).unwrap_or_default());
            }
            Ok(())
        };
        read_until_prompt(&mut monitor, &mut text)?;
        text.clear();
        monitor.write_all(format!("xp /1wx {address:#010x}\n").as_bytes())?;
        read_until_prompt(&mut monitor, &mut text)?;
        let text = String::from_utf8_lossy(&text);
        // The answer line: `0000000048000400: 0xabcdef01`.
        let key = format!("{address:016x}: 0x");
        let value = text
            .find(&key)
            .and_then(|at| text.get(at + key.len()..))
            .and_then(|rest| rest.get(..8))
            .with_context(|| format!("no value for {address:#010x} in QEMU's answer {text:?}"))?;
        u32::from_str_radix(value, 16).with_context(|| format!("parsing {value:?}"))
    }

    /// Waits for QEMU to exit (after [`PilLink::end_of_run`]).
    pub fn wait(mut self, timeout: Duration) -> Result<ExitStatus> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(status) = self.child.try_wait()? {
                return Ok(status);
            }
            if Instant::now() > deadline {
                bail!("QEMU did not exit within {timeout:?}");
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            self.child.kill().ok();
            self.child.wait().ok();
        }
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// A stand-in `qemu-system-arm` that lists `machines` for `-machine help`.
    fn fake_qemu(dir: &Path, machines: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let path = dir.join("qemu-system-arm");
        std::fs::write(&path, format!("#!/bin/sh\nprintf '%s\\n' '{machines}'\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    }

    #[test]
    fn an_old_qemu_without_the_board_is_refused_with_the_fix() {
        let dir = tempfile::tempdir().unwrap();
        // Bookworm's QEMU 7.2 lists other STM32 boards but not this one.
        let old = fake_qemu(dir.path(), "netduino2 Netduino 2 Machine (Cortex-M3)");
        let why = with_board_machine(old).unwrap_err();
        assert!(why.contains("no b-l475e-iot01a machine"), "{why}");
        assert!(why.contains("apt-get install"), "the fix is named: {why}");
        let new = fake_qemu(dir.path(), "b-l475e-iot01a B-L475E-IOT01A Discovery Kit (Cortex-M4)");
        assert_eq!(with_board_machine(new.clone()), Ok(new));
    }
}

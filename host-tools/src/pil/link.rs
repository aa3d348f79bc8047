//! The host end of the PIL frame link: QEMU's USART1 on a TCP socket (with
//! TCP_NODELAY: without it a round trip takes ~48 ms), or a serial port (a
//! real board's ST-LINK VCP, or QEMU's USART1 on a pty in the tests).
use super::ControlBackend;
use anyhow::{bail, Context, Result};
use mre_algorithm::control::ControlConfig;
use mre_algorithm::table::Table;
use mre_algorithm::Flags;
use mre_protocol::frame::{
    config_frames, encode_config, CommandFrame, SampleFrame, CONFIG_MAX_WORDS, END_OF_RUN_SEQ, FRAME_LEN, HELLO_SEQ,
    SYNC,
};
use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::time::{Duration, Instant};

/// No answer within this much wall time means the firmware is stuck.
pub const ANSWER_TIMEOUT: Duration = Duration::from_secs(10);
/// Serial handshake: a ping every this often until a hello arrives.
const PING_INTERVAL: Duration = Duration::from_secs(2);
/// The line is quiet this long after the hello: no late answer is pending.
const QUIET: Duration = Duration::from_millis(300);
/// ST-LINK VCP rate; QEMU's pty ignores it.
pub const BAUD: u32 = 115_200;

/// A byte stream to the firmware with a read timeout.
pub trait Transport: Read + Write + Send {
    fn set_read_timeout(&mut self, timeout: Duration) -> Result<()>;
}

impl Transport for TcpStream {
    fn set_read_timeout(&mut self, timeout: Duration) -> Result<()> {
        TcpStream::set_read_timeout(self, Some(timeout)).context("read timeout")
    }
}

impl Transport for Box<dyn serialport::SerialPort> {
    fn set_read_timeout(&mut self, timeout: Duration) -> Result<()> {
        self.set_timeout(timeout).context("serial port timeout")
    }
}

/// Opens a serial port raw, 115200 8N1 (a board's VCP, or a pty).
pub fn open_serial(port: &Path) -> Result<Box<dyn serialport::SerialPort>> {
    let name = port.to_str().context("serial port path is not UTF-8")?;
    serialport::new(name, BAUD)
        .timeout(ANSWER_TIMEOUT)
        .open()
        .with_context(|| format!("opening serial port {name}"))
}

pub struct PilLink {
    stream: Box<dyn Transport>,
    /// Received bytes not yet decoded (a frame may arrive in pieces).
    pending: Vec<u8>,
    frames: u64,
}

impl PilLink {
    /// QEMU's socket (`wait=on`: QEMU starts the firmware once this end is
    /// connected). Waits for the firmware's boot hello before anything is
    /// sent: bytes sent while it still boots could be lost.
    pub fn new(stream: TcpStream) -> Result<Self> {
        stream.set_nodelay(true).context("TCP_NODELAY")?;
        let mut link = Self::over(Box::new(stream))?;
        let hello = link.read_command().context("waiting for the firmware's hello frame")?;
        if hello.seq != HELLO_SEQ {
            bail!(
                "expected the hello frame (sequence {HELLO_SEQ}), got sequence {}",
                hello.seq
            );
        }
        Ok(link)
    }

    /// A serial port to a running board: its boot hello is long gone, so
    /// the link is opened by [`Self::handshake`].
    pub fn serial(port: &Path, timeout: Duration) -> Result<Self> {
        let mut link = Self::over(Box::new(open_serial(port)?))?;
        link.handshake(timeout)
            .with_context(|| format!("no hello from the firmware on {}", port.display()))?;
        Ok(link)
    }

    fn over(mut stream: Box<dyn Transport>) -> Result<Self> {
        stream.set_read_timeout(ANSWER_TIMEOUT)?;
        Ok(Self {
            stream,
            pending: Vec::new(),
            frames: 0,
        })
    }

    /// Pings ([`SampleFrame::ping`]) until the firmware answers
    /// with a hello, then waits for the line to go quiet so that no late
    /// answer to an earlier ping is taken for a later answer.
    pub fn handshake(&mut self, timeout: Duration) -> Result<()> {
        let deadline = Instant::now() + timeout;
        self.stream.set_read_timeout(PING_INTERVAL)?;
        let ping = SampleFrame::ping();
        let result = loop {
            if Instant::now() > deadline {
                break Err(anyhow::anyhow!("no hello within {timeout:?}"));
            }
            self.stream.write_all(&ping.encode()).context("sending ping")?;
            match self.read_command() {
                Ok(c) if c.seq == HELLO_SEQ => break Ok(()),
                Ok(_) | Err(_) => continue,
            }
        };
        result?;
        self.drain_until_quiet()?;
        self.stream.set_read_timeout(ANSWER_TIMEOUT)
    }

    fn drain_until_quiet(&mut self) -> Result<()> {
        self.pending.clear();
        self.stream.set_read_timeout(QUIET)?;
        let mut buf = [0u8; 64];
        loop {
            match self.stream.read(&mut buf) {
                Ok(0) => return Ok(()),
                Ok(_) => continue,
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => return Ok(()),
                Err(e) => return Err(e).context("reading the serial port"),
            }
        }
    }

    /// Reads the next valid command frame, resynchronising on the sync word
    /// (line noise or a partial frame on a serial port costs only those
    /// bytes). Fails on the read timeout.
    pub fn read_command(&mut self) -> Result<CommandFrame> {
        loop {
            while !self.pending.is_empty() && !SYNC.starts_with(&self.pending[..self.pending.len().min(2)]) {
                self.pending.remove(0);
            }
            if let Some(frame) = self.pending.get(..FRAME_LEN) {
                let frame: [u8; FRAME_LEN] = frame.try_into()?;
                match CommandFrame::decode(&frame) {
                    Ok(c) => {
                        self.pending.drain(..FRAME_LEN);
                        return Ok(c);
                    }
                    Err(_) => {
                        self.pending.remove(0);
                        continue;
                    }
                }
            }
            let mut chunk = [0u8; 64];
            let n = self.stream.read(&mut chunk)?;
            if n == 0 {
                bail!("the link was closed");
            }
            self.pending.extend_from_slice(&chunk[..n]);
        }
    }

    /// Sends one sample and waits for its command frame.
    pub fn exchange(&mut self, sample: &SampleFrame) -> Result<CommandFrame> {
        self.stream
            .write_all(&sample.encode())
            .context("sending sample frame")?;
        let cmd = self
            .read_command()
            .with_context(|| format!("no valid answer to sample {}", sample.seq))?;
        if cmd.seq != sample.seq {
            bail!("answer to sequence {} arrived for sample {}", cmd.seq, sample.seq);
        }
        self.frames += 1;
        Ok(cmd)
    }

    /// Uploads the controller's table and configuration (before the first
    /// sample) and waits for the firmware to accept them.
    pub fn upload_config(&mut self, table: &Table, cfg: &ControlConfig) -> Result<()> {
        let mut words = [0u32; CONFIG_MAX_WORDS];
        let n = encode_config(table, cfg, &mut words);
        let answer = self.send_config_words(&words[..n])?;
        if answer.flags.contains(Flags::TABLE_FAULT) {
            bail!("the firmware refused the uploaded table or configuration");
        }
        Ok(())
    }

    /// Sends a configuration blob (config frames + commit) and returns the
    /// firmware's answer, a hello flagged `TABLE_FAULT` if it refused.
    pub fn send_config_words(&mut self, words: &[u32]) -> Result<CommandFrame> {
        self.send_config_frames(config_frames(words))
    }

    /// Sends config frames (tests corrupt some) and returns the answer to
    /// the commit.
    pub fn send_config_frames(&mut self, frames: impl IntoIterator<Item = [u8; FRAME_LEN]>) -> Result<CommandFrame> {
        for frame in frames {
            self.stream.write_all(&frame).context("sending config frame")?;
        }
        let answer = self
            .read_command()
            .context("waiting for the firmware to accept the configuration")?;
        if answer.seq != HELLO_SEQ {
            bail!(
                "expected the configuration answer (sequence {HELLO_SEQ}), got sequence {}",
                answer.seq
            );
        }
        Ok(answer)
    }

    /// How long to wait for an answer (default [`ANSWER_TIMEOUT`]).
    pub fn set_answer_timeout(&mut self, timeout: Duration) -> Result<()> {
        self.stream.set_read_timeout(timeout)
    }

    /// Sends raw bytes (tests use it to inject corrupt frames).
    pub fn send_raw(&mut self, bytes: &[u8]) -> Result<()> {
        self.stream.write_all(bytes).context("sending raw bytes")
    }

    /// Tells the firmware the run is over; it exits QEMU with status 0.
    pub fn end_of_run(&mut self) -> Result<()> {
        let end = SampleFrame {
            seq: END_OF_RUN_SEQ,
            x_mm: 0.0,
            v_m_s: None,
            force_n: None,
            coil_current_a: None,
        };
        self.stream.write_all(&end.encode()).context("sending end of run")
    }

    pub fn frames(&self) -> u64 {
        self.frames
    }
}

impl ControlBackend for PilLink {
    fn step(&mut self, sample: &SampleFrame) -> Result<CommandFrame> {
        self.exchange(sample)
    }
}

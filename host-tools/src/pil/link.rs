//! The host end of the PIL frame link: a TCP socket to QEMU's USART1
//! chardev, with TCP_NODELAY (without it a round trip takes ~48 ms).
use super::ControlBackend;
use anyhow::{bail, Context, Result};
use mre_core::control::ControlConfig;
use mre_core::frame::{
    encode_config, CommandFrame, ConfigChunk, SampleFrame, CONFIG_MAX_WORDS, END_OF_RUN_SEQ, FRAME_LEN, HELLO_SEQ,
};
use mre_core::table::Table;
use mre_core::Flags;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// No answer within this much wall time means the firmware is stuck.
pub const ANSWER_TIMEOUT: Duration = Duration::from_secs(10);

pub struct PilLink {
    stream: TcpStream,
    frames: u64,
}

impl PilLink {
    /// Waits for the firmware's hello frame before anything is sent: bytes
    /// sent while it still boots could be lost.
    pub fn new(stream: TcpStream) -> Result<Self> {
        stream.set_nodelay(true).context("TCP_NODELAY")?;
        stream.set_read_timeout(Some(ANSWER_TIMEOUT)).context("read timeout")?;
        let mut link = Self { stream, frames: 0 };
        let hello = link.read_command().context("waiting for the firmware's hello frame")?;
        if hello.seq != HELLO_SEQ {
            bail!(
                "expected the hello frame (sequence {HELLO_SEQ}), got sequence {}",
                hello.seq
            );
        }
        Ok(link)
    }

    /// Reads the next command frame (fault injection reads answers itself).
    pub fn read_command(&mut self) -> Result<CommandFrame> {
        let mut buf = [0u8; FRAME_LEN];
        self.stream.read_exact(&mut buf)?;
        CommandFrame::decode(&buf).map_err(|e| anyhow::anyhow!("bad command frame: {e:?}"))
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
        let n = words.len();
        for (k, chunk) in words.chunks(3).enumerate() {
            let mut three = [0u32; 3];
            three[..chunk.len()].copy_from_slice(chunk);
            let frame = ConfigChunk::Words {
                index: 3 * k as u32,
                count: chunk.len() as u8,
                words: three,
            };
            self.stream.write_all(&frame.encode()).context("sending config frame")?;
        }
        self.stream
            .write_all(&ConfigChunk::Commit { total_words: n as u32 }.encode())
            .context("sending config commit")?;
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
        self.stream.set_read_timeout(Some(timeout)).context("read timeout")
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

//! Waiting for the device, where GL's wait runs out before a software rasterizer is done.

use super::RenderError;

/// Most times [`wait_for`] waits again when a wait runs out.
const WAITS: u32 = 100;

/// Blocks until `device` has finished all submitted work. Even told to wait indefinitely, GL
/// waits at most about 2.1 s (its fence wait takes a 32-bit count of nanoseconds), less than a
/// large submission takes on a software rasterizer: a wait that runs out is made again, up to
/// [`WAITS`] times, before it is an error.
pub fn wait_for(device: &wgpu::Device) -> Result<(), RenderError> {
    let mut runs_out = 0;
    loop {
        match device.poll(wgpu::PollType::wait_indefinitely()) {
            Err(wgpu::PollError::Timeout) if runs_out < WAITS => runs_out += 1,
            done => return done.map(|_| ()).map_err(|e| RenderError::Wgpu(e.to_string())),
        }
    }
}

//! Serial-port discovery and opening. Uses serialport without libudev: USB VID/PID come from
//! `/sys` on Linux.

use std::time::Duration;

use crate::HwError;

/// USB vendor ID of the PAROL6 board (STMicroelectronics).
pub const PAROL6_VID: u16 = 0x0483;
/// USB product ID of the PAROL6 board (STM32 virtual COM port).
pub const PAROL6_PID: u16 = 0x5740;
/// Baud rate the official hosts use (ignored by USB CDC).
pub const BAUD_RATE: u32 = 3_000_000;

/// One serial port seen on the system.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct PortInfo {
    /// Path or name (`/dev/ttyACM0`, `COM3`).
    pub name: String,
    /// USB vendor ID, if a USB device.
    pub vid: Option<u16>,
    /// USB product ID, if a USB device.
    pub pid: Option<u16>,
    /// USB serial number.
    pub serial_number: Option<String>,
    /// USB manufacturer string.
    pub manufacturer: Option<String>,
    /// USB product string.
    pub product: Option<String>,
    /// True when VID:PID is 0483:5740.
    pub is_parol6: bool,
}

/// Lists the serial ports, PAROL6 boards first.
pub fn list_ports() -> Result<Vec<PortInfo>, HwError> {
    let ports = serialport::available_ports().map_err(|e| HwError::ListPorts(e.to_string()))?;
    let mut out: Vec<PortInfo> = ports
        .into_iter()
        .map(|p| match p.port_type {
            serialport::SerialPortType::UsbPort(u) => PortInfo {
                name: p.port_name,
                vid: Some(u.vid),
                pid: Some(u.pid),
                serial_number: u.serial_number,
                manufacturer: u.manufacturer,
                product: u.product,
                is_parol6: u.vid == PAROL6_VID && u.pid == PAROL6_PID,
            },
            _ => PortInfo {
                name: p.port_name,
                vid: None,
                pid: None,
                serial_number: None,
                manufacturer: None,
                product: None,
                is_parol6: false,
            },
        })
        .collect();
    out.sort_by(|a, b| b.is_parol6.cmp(&a.is_parol6).then_with(|| a.name.cmp(&b.name)));
    Ok(out)
}

/// The first port whose USB VID:PID is 0483:5740.
pub fn find_parol6_port() -> Result<String, HwError> {
    let ports = list_ports()?;
    if let Some(p) = ports.iter().find(|p| p.is_parol6) {
        return Ok(p.name.clone());
    }
    let seen = if ports.is_empty() {
        "none".to_string()
    } else {
        ports.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ")
    };
    Err(HwError::NotFound { seen })
}

/// Maps a serialport error to an [`HwError`] that explains permission problems.
pub fn open_error(port: &str, e: &serialport::Error) -> HwError {
    let denied = matches!(e.kind, serialport::ErrorKind::Io(std::io::ErrorKind::PermissionDenied))
        || e.description.contains("Permission denied")
        || e.description.contains("EACCES");
    if denied {
        HwError::PermissionDenied { port: port.to_string() }
    } else {
        HwError::PortOpen { port: port.to_string(), reason: e.description.clone() }
    }
}

/// Read / write timeout of a freshly opened port (the session sets its own per read).
const OPEN_TIMEOUT: Duration = Duration::from_millis(5);

/// Opens `port` at 3 000 000 baud, 8N1, no flow control. A path that is a Unix-domain socket
/// is the fake robot's ([`crate::emulator::EmulatorHandle::spawn_socket`]): it is connected as a
/// socket with the same timeout; every other path is opened as a serial device.
pub fn open_port(port: &str) -> Result<Box<dyn serialport::SerialPort>, HwError> {
    #[cfg(unix)]
    if crate::socket_link::is_socket(port) {
        return Ok(Box::new(crate::socket_link::SocketPort::connect(port, OPEN_TIMEOUT)?));
    }
    serialport::new(port, BAUD_RATE)
        .data_bits(serialport::DataBits::Eight)
        .parity(serialport::Parity::None)
        .stop_bits(serialport::StopBits::One)
        .flow_control(serialport::FlowControl::None)
        .timeout(OPEN_TIMEOUT)
        .open()
        .map_err(|e| open_error(port, &e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permission_error_explains_dialout_and_udev() {
        let e = serialport::Error::new(
            serialport::ErrorKind::Io(std::io::ErrorKind::PermissionDenied),
            "Permission denied",
        );
        let msg = open_error("/dev/ttyACM0", &e).to_string();
        assert!(msg.contains("dialout") && msg.contains("udev") && msg.contains("0483"), "{msg}");
    }

    #[test]
    fn missing_port_is_a_clear_error() {
        let err = match open_port("/dev/does-not-exist-parol6") {
            Ok(_) => panic!("opened a missing port"),
            Err(e) => e,
        };
        assert!(matches!(err, HwError::PortOpen { .. }), "{err:?}");
    }

    #[test]
    fn listing_ports_does_not_fail() {
        let ports = list_ports().expect("list");
        // PAROL6 boards come first.
        let first_non = ports.iter().position(|p| !p.is_parol6).unwrap_or(ports.len());
        assert!(ports[first_non..].iter().all(|p| !p.is_parol6));
    }
}

use super::codec::{get_i24, put_i24};
use super::*;
use proptest::prelude::*;

#[test]
fn i24_round_trip_edges() {
    let mut b = [0u8; 3];
    for v in [I24_MIN, -65536, -1, 0, 1, 65535, I24_MAX] {
        put_i24(&mut b, v);
        assert_eq!(get_i24(&b), v);
    }
    put_i24(&mut b, -1);
    assert_eq!(b, [0xFF, 0xFF, 0xFF]);
}

#[test]
fn no_code_69_or_200() {
    for c in CommandCode::ALL {
        assert_ne!(c.byte(), 69);
        assert_ne!(c.byte(), 200);
        assert_eq!(CommandCode::from_byte(c.byte()), Some(c));
    }
    assert_eq!(CommandCode::from_byte(69), None);
    assert_eq!(CommandCode::from_byte(200), None);
}

#[test]
fn home_frame_matches_protocol_md_8_1() {
    let b = CommandFrame::new(CommandCode::Home).encode().unwrap();
    let mut expected = vec![0xFF, 0xFF, 0xFF, 0x34];
    expected.extend([0u8; 36]);
    expected.push(0x64);
    expected.extend([0u8; 12]);
    expected.extend([0xE4, 0x01, 0x02]);
    assert_eq!(b.to_vec(), expected);
}

#[test]
fn encode_rejects_out_of_range() {
    let mut f = CommandFrame::new(CommandCode::Move);
    f.fields.positions_steps[2] = I24_MAX + 1;
    assert!(matches!(f.encode(), Err(FrameError::OutOfRange { .. })));
}

#[test]
fn decode_rejects_bad_frames() {
    let good = StatusFrame::default().encode();
    assert!(StatusFrame::decode(&good).is_ok());
    assert!(matches!(StatusFrame::decode(&good[..59]), Err(FrameError::WrongSize { .. })));
    let mut b = good;
    b[3] = 0x34;
    assert!(matches!(StatusFrame::decode(&b), Err(FrameError::BadLength { .. })));
    let mut b = good;
    b[59] = 3;
    assert_eq!(StatusFrame::decode(&b), Err(FrameError::BadEnd));
    let mut b = good;
    b[1] = 0;
    assert_eq!(StatusFrame::decode(&b), Err(FrameError::BadStart));
    let mut b = good;
    b[57] = 0x00;
    assert!(StatusFrame::decode(&b).is_ok(), "CRC byte is ignored");
}

#[test]
fn default_status_is_unhomed_idle() {
    let s = StatusFrame::default();
    let b = s.encode();
    assert_eq!(&b[40..44], &[0x03, 0x0F, 0x03, 0x03]);
    assert!(!s.estop_pressed());
    assert!(!s.all_homed());
}

fn arb_status() -> impl Strategy<Value = StatusFrame> {
    (
        proptest::array::uniform6(I24_MIN..=I24_MAX),
        proptest::array::uniform6(I24_MIN..=I24_MAX),
        any::<[u8; 4]>(),
        any::<u16>(),
        any::<[u8; 3]>(),
        any::<[i16; 3]>(),
        any::<[u8; 2]>(),
    )
        .prop_map(|(p, s, bits, t, bytes, g, gs)| StatusFrame {
            positions_steps: p,
            speeds_steps_s: s,
            homed_bits: bits[0],
            io_bits: bits[1],
            temperature_error_bits: bits[2],
            position_error_bits: bits[3],
            timing_ticks: t,
            timeout_error: bytes[0],
            echoed_command: bytes[1],
            gripper_id: bytes[2],
            gripper_position: g[0],
            gripper_speed: g[1],
            gripper_current_ma: g[2],
            gripper_status: gs[0],
            gripper_object_byte: gs[1],
        })
}

proptest! {
    #[test]
    fn status_round_trip(s in arb_status()) {
        let b = s.encode();
        prop_assert_eq!(StatusFrame::decode(&b), Ok(s));
    }

    #[test]
    fn command_round_trip(
        code in proptest::sample::select(CommandCode::ALL.to_vec()),
        p in proptest::array::uniform6(I24_MIN..=I24_MAX),
        s in proptest::array::uniform6(I24_MIN..=I24_MAX),
        bytes in any::<[u8; 6]>(),
        g in any::<[i16; 3]>(),
    ) {
        let frame = CommandFrame { command: code, fields: CommandFields {
            positions_steps: p, speeds_steps_s: s, affected_joints: bytes[0], io_bits: bytes[1],
            timeout: bytes[2],
            gripper: GripperCommand { position: g[0], speed: g[1], current_ma: g[2],
                command_bits: bytes[3], mode: bytes[4], id: bytes[5] },
        }};
        let b = frame.encode().unwrap();
        let r = ReceivedCommand::decode(&b).unwrap();
        prop_assert_eq!(r.command(), Some(code));
        prop_assert_eq!(r.fields, frame.fields);
        prop_assert_eq!(r.crc_byte, COMMAND_CRC_BYTE);
    }

    #[test]
    fn decoders_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..128)) {
        let _ = StatusFrame::decode(&bytes);
        let _ = ReceivedCommand::decode(&bytes);
        let _ = ReceivedCommand::decode_payload(&bytes);
    }
}

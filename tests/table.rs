//! The RMoCap table reader and writer: error positions, round trips, and the
//! odd shapes real files come in.

// A test may panic on what it does not expect: that is how it fails.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use embusen::io::table::{Accelerations, Table};
use glam::DVec3;
use proptest::prelude::*;

const SMALL: &str = "\
Time,Hips.Dx,Hips.Dy,Hips.Dz,LeftFoot.Dx,LeftFoot.Dy,LeftFoot.Dz,Hips.Rx,LeftFoot.ax,LeftFoot.ay,LeftFoot.az
0,1,90,2,-10,5,0,30,0,1,0
0.01,1.5,90.5,2.5,-10,5,0,31,0.1,0.9,0
0.02,2,91,3,-10,5.5,0.25,32,0,1.1,0.2
";

fn parse(text: &str) -> Table {
    Table::parse(text.as_bytes(), "t.csv").unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> String {
    match Table::parse(text.as_bytes(), "t.csv") {
        Ok(_) => panic!("expected an error for {text:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn reads_positions_rotations_accelerations() {
    let t = parse(SMALL);
    assert_eq!(t.frame_count(), 3);
    assert_eq!(t.headers.len(), 11);
    assert_eq!(t.joint_names, ["Hips", "LeftFoot"]);
    assert_eq!(t.position_columns, [[1, 2, 3], [4, 5, 6]]);
    assert!(t.warnings.is_empty(), "{:?}", t.warnings);
    let frame_time = t.frame_time_s().unwrap();
    assert!((frame_time - 0.01).abs() < 1e-15);
    let poses = t.poses();
    assert_eq!(poses.joint_count, 2);
    assert_eq!(poses.at(2, 1), DVec3::new(-10.0, 5.5, 0.25));
    assert_eq!(t.column("Hips.Rx"), Some(vec![30.0, 31.0, 32.0]));
    assert_eq!(t.column("Nope"), None);
    assert_eq!(t.accel_g("LeftFoot").unwrap()[2], DVec3::new(0.0, 1.1, 0.2));
    assert_eq!(t.accel_g("Hips"), None);
    let a = Accelerations::from_table(&t);
    assert_eq!(a.sensor_names, ["LeftFoot"]);
    assert_eq!(a.frame_count(), 3);
    assert_eq!(a.sensor("LeftFoot").unwrap()[1], DVec3::new(0.1, 0.9, 0.0));
    assert!(a.sensor("Hips").is_none());
}

#[test]
fn a_letter_in_a_number_points_at_the_letter() {
    let text = SMALL.replace("0.01,1.5,90.5", "0.01,1.5,90x5");
    assert_eq!(error(&text), "t.csv:3:12: expected a number, found `90x5`");
    let text = SMALL.replace("0.01,1.5,", "0.01,abc,");
    assert_eq!(error(&text), "t.csv:3:6: expected a number, found `abc`");
}

#[test]
fn missing_values_and_non_finite_numbers_are_errors() {
    let text = SMALL.replace("0.01,1.5,", "0.01,NA,");
    let e = error(&text);
    assert!(e.starts_with("t.csv:3:6: expected a number, found `NA`"), "{e}");
    let text = SMALL.replace("0.01,1.5,", "0.01,,");
    assert_eq!(error(&text), "t.csv:3:6: expected a number, found an empty field");
    let text = SMALL.replace("0.01,1.5,", "0.01,Inf,");
    assert_eq!(error(&text), "t.csv:3:6: expected a finite number, found `Inf`");
    let text = SMALL.replace("0.01,1.5,", "0.01,NaN,");
    assert_eq!(error(&text), "t.csv:3:6: expected a finite number, found `NaN`");
}

#[test]
fn rows_with_the_wrong_number_of_fields() {
    let short = SMALL.replace("0.01,1.5,90.5,2.5,-10,5,0,31,0.1,0.9,0", "0.01,1.5,90.5");
    assert_eq!(error(&short), "t.csv:3:14: expected 11 fields, found 3");
    let long = SMALL.replace("0,1,90,2,-10,5,0,30,0,1,0", "0,1,90,2,-10,5,0,30,0,1,0,7,8");
    assert_eq!(error(&long), "t.csv:2:27: expected 11 fields, found 13");
}

#[test]
fn empty_file_header_only_and_bad_headers() {
    assert_eq!(error(""), "t.csv:1:1: the file is empty: expected a header row of column names");
    assert!(error("\n\r\n").contains("the file is empty"));
    assert_eq!(error("Time,Hips.Dx\n"), "t.csv:2:1: expected rows of numbers after the header, found none");
    assert_eq!(
        error("Time,Hips.Dx,Time\n1,2,3\n"),
        "t.csv:1:14: column name `Time` appears twice (first as column 1)"
    );
    assert_eq!(error("Time,,Hips.Dx\n1,2,3\n"), "t.csv:1:6: expected a column name, found an empty field");
    assert!(error("\"Time,Hips.Dx\n1\n").contains("quoted field never closes"));
    assert_eq!(
        error("\"Time\"x,Hips.Dx\n1,2\n"),
        "t.csv:1:7: expected `,` or the end of the line after a closing `\"`"
    );
}

#[test]
fn round_trip_parse_write_parse() {
    let mut t = parse(SMALL);
    // Values that need all 17 digits, tiny and huge ones, and negative zero.
    t.values[1] = 0.1 + 0.2;
    t.values[2] = -1.0e-300;
    t.values[3] = 6.02214076e23;
    t.values[4] = -0.0;
    t.values[5] = 2.5499999999999896;
    let text = t.write();
    let back = parse(&text);
    assert_eq!(back.headers, t.headers);
    assert_eq!(back.joint_names, t.joint_names);
    assert_eq!(back.position_columns, t.position_columns);
    for (a, b) in back.values.iter().zip(&t.values) {
        assert_eq!(a.to_bits(), b.to_bits());
    }
    assert_eq!(back, t);
    // And writing again gives the same text.
    assert_eq!(back.write(), text);
}

#[test]
fn with_shift_moves_every_position_column_only() {
    let t = parse(SMALL);
    let shift = [DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO, DVec3::new(-1.0, 0.0, 0.5)];
    let s = t.with_shift(&shift);
    let (before, after) = (t.poses(), s.poses());
    for (f, shift) in shift.iter().enumerate() {
        for j in 0..2 {
            assert_eq!(after.at(f, j), before.at(f, j) + *shift);
        }
    }
    for name in ["Time", "Hips.Rx", "LeftFoot.ax", "LeftFoot.ay", "LeftFoot.az"] {
        assert_eq!(s.column(name), t.column(name), "{name}");
    }
    // A short shift leaves the remaining frames alone.
    let s = t.with_shift(&shift[..1]);
    assert_eq!(s.poses().at(2, 0), before.at(2, 0));
}

#[test]
fn any_subset_of_columns() {
    let t = parse("LeftFoot.ax,LeftFoot.ay,LeftFoot.az\n0,1,0\n0,1.5,0\n");
    assert!(t.joint_names.is_empty());
    assert_eq!(t.poses().joint_count, 0);
    assert_eq!(t.frame_time_s(), None);
    let a = Accelerations::parse(b"LeftFoot.ax,LeftFoot.ay,LeftFoot.az\n0,1,0\n", "a.csv").unwrap();
    assert_eq!(a.sensor_names, ["LeftFoot"]);

    let t = parse("Hips.Dy,Hips.Dx,Hips.Dz,Foot.Dx\n1,2,3,4\n");
    assert_eq!(t.joint_names, ["Hips"]);
    assert_eq!(t.position_columns, [[1, 0, 2]]);
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    assert!(t.warnings[0].contains("`Foot`"), "{:?}", t.warnings);
    assert_eq!(t.poses().at(0, 0), DVec3::new(2.0, 1.0, 3.0));

    // No accelerometer columns: not an accelerometer file.
    let e = Accelerations::parse(b"Time,Hips.Dx\n0,1\n", "a.csv").unwrap_err();
    assert!(e.to_string().starts_with("a.csv: expected `<Sensor>.ax`"), "{e}");

    // Time that does not increase is not a frame time.
    let t = parse("Time,Hips.Dx\n0,1\n0,2\n");
    assert_eq!(t.frame_time_s(), None);
}

#[test]
fn crlf_and_quoted_r_headers_with_row_numbers() {
    let r_style = "\"\",\"Time\",\"Hips.Dx\",\"Hips.Dy\",\"Hips.Dz\",\"a \"\"quoted\"\" name\"\r\n\
                   \"1\",0,1,2,3,4\r\n\
                   \"2\",0.01,1.5,2.5,3.5,4.5\r\n";
    let t = parse(r_style);
    assert_eq!(t.headers, ["Time", "Hips.Dx", "Hips.Dy", "Hips.Dz", "a \"quoted\" name"]);
    assert_eq!(t.frame_count(), 2);
    assert_eq!(t.values, [0.0, 1.0, 2.0, 3.0, 4.0, 0.01, 1.5, 2.5, 3.5, 4.5]);
    assert_eq!(t.warnings.len(), 1);
    assert!(t.warnings[0].contains("row numbers"), "{:?}", t.warnings);
    // The quoted name survives a round trip.
    assert_eq!(parse(&t.write()).headers, t.headers);

    let crlf = SMALL.replace('\n', "\r\n");
    assert_eq!(parse(&crlf), parse(SMALL));
    // Errors on CRLF lines still point at the right column.
    let bad = crlf.replace("0.02,2,91", "0.02,2,9q");
    assert_eq!(error(&bad), "t.csv:4:9: expected a number, found `9q`");
    // No final line end, a byte-order mark, blank lines.
    let no_end = format!("\u{feff}{}", SMALL.trim_end().replace("0.01,", "\n0.01,"));
    assert_eq!(parse(&no_end).values, parse(SMALL).values);
}

proptest! {
    #[test]
    fn parsers_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let _ = Table::parse(&bytes, "p.csv");
        let _ = Accelerations::parse(&bytes, "p.csv");
    }

    #[test]
    fn parsers_never_panic_on_csv_like_bytes(
        bytes in proptest::collection::vec(
            prop_oneof![
                Just(b','), Just(b'"'), Just(b'\n'), Just(b'\r'), Just(b'.'), Just(b'-'),
                Just(b'e'), Just(b'x'), Just(b'D'), Just(b'a'), Just(b' '), b'0'..=b'9',
            ],
            0..400,
        )
    ) {
        let text = [b"Time,A.Dx,A.Dy,A.Dz,A.ax,A.ay,A.az\n".as_slice(), &bytes].concat();
        let _ = Table::parse(&text, "p.csv");
        let _ = Accelerations::parse(&text, "p.csv");
        let _ = Table::parse(&bytes, "p.csv");
    }
}

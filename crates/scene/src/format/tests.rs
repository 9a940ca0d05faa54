//! Unit tests of the formatter: layouts, comments kept, idempotence.

use super::format;

fn fmt(text: &str) -> String {
    format(text).expect("no syntax errors")
}

#[test]
fn lays_out_sections_and_attributes() {
    assert_eq!(
        fmt("camera 4 sphere dimension 1 center 0 0 -5\n\n\n\nlight location 1 1 1 color 1 1 1"),
        "camera 4\n\nsphere\n  dimension 1\n  center 0 0 -5\n\nlight\n  location 1 1 1\n  color 1 1 1\n"
    );
}

#[test]
fn keeps_comments_where_they_belong() {
    let text = "# header\n\n# about the camera\ncamera 4 # square\nsphere\n# the size\ndimension .5   # radius\n  center 0 # x\n 0 -5\n  # color 1 0 0\n# the end\n";
    assert_eq!(
        fmt(text),
        "# header\n\n# about the camera\ncamera 4 # square\n\nsphere\n  # the size\n  dimension 0.5 # radius\n  center 0      # x\n    0 -5\n  # color 1 0 0\n\n# the end\n"
    );
}

#[test]
fn is_idempotent_on_its_examples() {
    for text in [
        "camera 4\n\n\nsphere dimension 1 center 0 0 -5 # c\n",
        "# a\n# b\ncamera 4\n# c\n\n\n# d\nsphere center # x\n 1 2 3",
        "\u{feff}camera\t4\r\nsphere texture \"a b#.ppm\"#t\r\n",
    ] {
        let once = fmt(text);
        assert_eq!(fmt(&once), once, "{text:?}");
    }
}

#[test]
fn refuses_syntax_errors() {
    assert!(format("camera 4,5").is_err());
    assert!(format("1 2 camera 4").is_err());
}

#[test]
fn empty_and_comment_only_files() {
    assert_eq!(fmt(""), "");
    assert_eq!(fmt("  \n\n"), "");
    assert_eq!(fmt("# only\n\n\n# two  \n"), "# only\n\n# two\n");
}

/// One canonical form with `convert --to scene` (issue 56): numbers as
/// [`super::number`] spells them, attributes in the language table's
/// order, each with its comments; what a section does not take goes last.
#[test]
fn spells_numbers_and_orders_attributes_canonically() {
    assert_eq!(
        fmt("camera 4e2\nsphere\n  reflectivity .7 # shiny\n  # grey\n  color .3 .3 .3\n  colour 1\n  center +0 1. -5\n  dimension 1e-7\n  # left over\n"),
        "camera 400\n\nsphere\n  dimension 1e-7\n  center 0 1 -5\n  # grey\n  color 0.3 0.3 0.3\n  reflectivity 0.7 # shiny\n  colour 1\n  # left over\n"
    );
    assert_eq!(
        fmt("plane headup 0 0 -1 normal 0 1 0 center 0 -1 -5 dimension 4 4"),
        "plane\n  dimension 4 4\n  center 0 -1 -5\n  normal 0 1 0\n  headup 0 0 -1\n"
    );
}

//! `results.json` in Gradescope's autograder format: the total `score`,
//! and one test per scene with its `name`, `score`, `max_score`, `output`
//! (the status, the metrics and the program's stderr) and `visibility`.

use serde::Serialize;

use super::Summary;
use crate::grade::SceneResult;

/// The whole file.
#[derive(Serialize)]
pub struct Results {
    pub score: f64,
    pub output: String,
    pub tests: Vec<Test>,
}

/// One scene as a Gradescope test.
#[derive(Serialize)]
pub struct Test {
    pub name: String,
    pub score: f64,
    pub max_score: f64,
    pub output: String,
    pub visibility: &'static str,
}

/// The results of `summary`.
pub fn results(summary: &Summary) -> Results {
    Results {
        score: summary.score,
        output: format!(
            "{} of {} scenes match; {} of {} points (raytracer grade)",
            summary
                .scenes
                .iter()
                .filter(|s| s.status == crate::grade::Status::Match)
                .count(),
            summary.scenes.len(),
            summary.score,
            summary.max_score
        ),
        tests: summary.scenes.iter().map(test).collect(),
    }
}

fn test(scene: &SceneResult) -> Test {
    let name = if scene.description.is_empty() {
        scene.scene.clone()
    } else {
        format!("{}: {}", scene.scene, scene.description)
    };
    Test {
        name,
        score: scene.score,
        max_score: scene.points,
        output: super::outcome_lines(scene).join("\n"),
        visibility: "visible",
    }
}

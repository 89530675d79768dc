//! A SilverLode lesson and an answer that fails one of its checks.

/// A SilverLode lesson whose program stores 1015 where the task asks for 1016.
pub const LESSON: &str = r##"(
  format: 2,
  dialect: "silverlode",
  program_name: "scaling.qsl",
  program: "DEF mm_per_count = q16(0.0254)\n        WRP 20, 40000\n        CLD MULT_S64_SHR16, 21, 20, mm_per_count\n        CLC DEC, 21\n        END\n",
  lesson: Some((
    title: "Scaling",
    steps: [
      (text: "# Read\nNothing to check here.", checks: []),
      (text: "Make **R21** hold 1016.", checks: ["R21 == 1016", "R20 == 40000"]),
    ],
  )),
)"##;

pub const ANSWER: &str = "DEF mm_per_count = q16(0.0254)
        WRP 20, 40000
        CLD MULT_S64_SHR16, 21, 20, mm_per_count
        END
";

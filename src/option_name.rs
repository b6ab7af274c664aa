//! The options of the library's calls as values. An [`Error::Option`](crate::Error::Option)
//! names one; each face spells it in one function of its own (the CLI's flags, Python's
//! arguments, the FMU's log), so no library message spells a flag.

/// One option of a library call; its name is the library's spelling (`SimulationOptions::dt`).
/// Not `non_exhaustive`: a face's spelling is an exhaustive match, so a new option cannot go
/// unspelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OptionName {
    /// `SimulationOptions::method`.
    Method,
    /// `SimulationOptions::rtol` and `atol` together.
    Tolerances,
    /// `SimulationOptions::dt` (s).
    Dt,
    /// `SimulationOptions::accuracy` (m).
    Accuracy,
    /// `SimulationOptions::moment_tolerance`.
    MomentTolerance,
    /// `SimulationOptions::statistics_tolerance`.
    StatisticsTolerance,
    /// `SimulationOptions::stations` (m).
    Stations,
    /// `SimulationOptions::modes_as_given`.
    ModesAsGiven,
    /// `SimulationOptions::model`: which model computes the right-hand side.
    Model,
    /// The memory budget (bytes) of a call's options.
    MemoryBudget,
    /// A controller file given to a run.
    Controller,
    /// `DesignOptions::kind`.
    ControllerKind,
    /// `DesignOptions::design_modes`.
    DesignModes,
    /// `DesignOptions::force_limit` (N).
    ForceLimit,
    /// `DesignOptions::tip_scale` (m).
    TipScale,
    /// `DesignOptions::vehicle_scale` (m).
    VehicleScale,
    /// `DesignOptions::sensors`.
    Sensors,
    /// `DesignOptions::sensor_noises`.
    SensorNoises,
    /// `DesignOptions::estimator`.
    Estimator,
    /// `DesignOptions::rate_hz` (Hz).
    RateHz,
    /// `DesignOptions::law`.
    Law,
    /// `DesignOptions::added_damping`.
    AddedDamping,
    /// `DesignOptions::sensor_noise` (m).
    SensorNoise,
    /// `DesignOptions::force_noise` (N).
    ForceNoise,
    /// `DesignOptions::process_noise_floor`.
    ProcessNoiseFloor,
    /// `DesignOptions::grid_points`.
    GridPoints,
    /// `SweepOptions::jobs`.
    Jobs,
    /// `SweepOptions::resume`.
    Resume,
    /// `SweepOptions::out`.
    SweepOut,
    /// A shard from a job array's variables (`Shard::of_job_array`).
    Shard,
    /// The shard count given to `Shard::of_job_array`.
    ShardCount,
    /// The x column of a sweep chart.
    ChartX,
    /// The y column of a sweep chart.
    ChartY,
    /// The color column of a sweep chart.
    ChartColor,
    /// A sweep chart drawn as a heat map.
    ChartHeatmap,
    /// `ShapeErrorsOptions::length` (m).
    ShapeLength,
    /// `ShapeErrorsOptions::points`.
    ShapePoints,
    /// `ConvergeOptions::tol`.
    ConvergeTol,
    /// `ConvergeOptions::max_modes`.
    MaxModes,
    /// `ConvergeOptions::max_contacts`.
    MaxContacts,
    /// `WorkPrecisionOptions::repeat`.
    Repeat,
    /// `WorkPrecisionOptions::methods`.
    Methods,
    /// `WorkPrecisionOptions::rtols`.
    Rtols,
    /// `ModelSizeOptions::sizes`.
    Sizes,
    /// `ModesOptions::at` (s).
    ModesAt,
    /// `ModesOptions::count`.
    ModesCount,
    /// `ModesOptions::shapes`.
    Shapes,
    /// The LaTeX format of a linear export.
    LatexFormat,
    /// `LinearizeOptions::at_time` (s).
    AtTime,
    /// `LinearizeOptions::positions` (m).
    Positions,
    /// `LinearizeOptions::grid`.
    Grid,
    /// `LinearizeOptions::discrete` (s).
    Discrete,
    /// `BodeOptions::linear`.
    BodeLinear,
    /// `BodeOptions::inputs`.
    BodeInputs,
    /// `BodeOptions::outputs`.
    BodeOutputs,
    /// `BodeOptions::from_hz` (Hz).
    FromHz,
    /// `BodeOptions::to_hz` (Hz).
    ToHz,
    /// `BodeOptions::points`.
    BodePoints,
    /// The shared library an FMU archive packs.
    FmuLibrary,
    /// `AnimationOptions::fps` (frames per second of simulation time).
    Fps,
    /// `AnimationOptions::scale`: the transverse deflection's exaggeration.
    DeflectionScale,
    /// `AnimationOptions::size` (pixels) of a GIF.
    AnimationSize,
    /// `AnimationOptions::speed`: simulation seconds per second of a GIF.
    AnimationSpeed,
    /// `MoveLimits::distance` (m).
    Distance,
    /// `MoveLimits::v_max`, `a_max`, `j_max`.
    MoveLimits,
    /// `PlanOptions::tolerance` (m).
    MoveTolerance,
    /// `PlanOptions::margin`: the share of the tolerance a pick keeps in reserve.
    MoveMargin,
    /// `PlanOptions::settle_s` (s).
    Settle,
    /// `PlanOptions::robust`.
    Robust,
    /// `PlanOptions::checks`: plants the best plan is checked on.
    Checks,
    /// `PlanOptions::feedback`: the velocity feedback's design.
    Feedback,
    /// `VelocityDesign::velocity_limit` and `acceleration_limit`: the correction's bounds.
    CorrectionLimits,
    /// `ControllerFile::with_weighed_load`: the load a velocity feedback is told (kg).
    WeighedLoad,
    /// The candidate of a plan to write instead of the best (`MovePlan::candidate_named`).
    Pick,
    /// The setpoint filter emitted as C (`plan::emit::emit_filter_c`).
    EmitC,
    /// The emitted setpoint filter's rate (Hz).
    FilterRate,
    /// `IdentifyOptions::free`: the scene values a fit frees.
    Free,
    /// `IdentifyOptions::noise`: the sensors' noise given.
    Noise,
    /// `IdentifyOptions::start`: a record that starts at rest or in motion.
    Start,
}

crate::named::named_enum!(OptionName, "an option", {
    Method => "SimulationOptions::method",
    Tolerances => "SimulationOptions::rtol/atol",
    Dt => "SimulationOptions::dt",
    Accuracy => "SimulationOptions::accuracy",
    MomentTolerance => "SimulationOptions::moment_tolerance",
    StatisticsTolerance => "SimulationOptions::statistics_tolerance",
    Stations => "SimulationOptions::stations",
    ModesAsGiven => "SimulationOptions::modes_as_given",
    Model => "SimulationOptions::model",
    MemoryBudget => "memory_budget",
    Controller => "controller",
    ControllerKind => "DesignOptions::kind",
    DesignModes => "DesignOptions::design_modes",
    ForceLimit => "DesignOptions::force_limit",
    TipScale => "DesignOptions::tip_scale",
    VehicleScale => "DesignOptions::vehicle_scale",
    Sensors => "DesignOptions::sensors",
    SensorNoises => "DesignOptions::sensor_noises",
    Estimator => "DesignOptions::estimator",
    RateHz => "DesignOptions::rate_hz",
    Law => "DesignOptions::law",
    AddedDamping => "DesignOptions::added_damping",
    SensorNoise => "DesignOptions::sensor_noise",
    ForceNoise => "DesignOptions::force_noise",
    ProcessNoiseFloor => "DesignOptions::process_noise_floor",
    GridPoints => "DesignOptions::grid_points",
    Jobs => "SweepOptions::jobs",
    Resume => "SweepOptions::resume",
    SweepOut => "SweepOptions::out",
    Shard => "Shard::of_job_array",
    ShardCount => "Shard::of_job_array count",
    ChartX => "SweepChart x",
    ChartY => "SweepChart y",
    ChartColor => "SweepChart color",
    ChartHeatmap => "SweepChart heatmap",
    ShapeLength => "ShapeErrorsOptions::length",
    ShapePoints => "ShapeErrorsOptions::points",
    ConvergeTol => "ConvergeOptions::tol",
    MaxModes => "ConvergeOptions::max_modes",
    MaxContacts => "ConvergeOptions::max_contacts",
    Repeat => "WorkPrecisionOptions::repeat",
    Methods => "WorkPrecisionOptions::methods",
    Rtols => "WorkPrecisionOptions::rtols",
    Sizes => "ModelSizeOptions::sizes",
    ModesAt => "ModesOptions::at",
    ModesCount => "ModesOptions::count",
    Shapes => "ModesOptions::shapes",
    LatexFormat => "LinearExport format latex",
    AtTime => "LinearizeOptions::at_time",
    Positions => "LinearizeOptions::positions",
    Grid => "LinearizeOptions::grid",
    Discrete => "LinearizeOptions::discrete",
    BodeLinear => "BodeOptions::linear",
    BodeInputs => "BodeOptions::inputs",
    BodeOutputs => "BodeOptions::outputs",
    FromHz => "BodeOptions::from_hz",
    ToHz => "BodeOptions::to_hz",
    BodePoints => "BodeOptions::points",
    FmuLibrary => "fmu library",
    Fps => "AnimationOptions::fps",
    DeflectionScale => "AnimationOptions::scale",
    AnimationSize => "AnimationOptions::size",
    AnimationSpeed => "AnimationOptions::speed",
    Distance => "MoveLimits::distance",
    MoveLimits => "MoveLimits::v_max/a_max/j_max",
    MoveTolerance => "PlanOptions::tolerance",
    MoveMargin => "PlanOptions::margin",
    Settle => "PlanOptions::settle_s",
    Robust => "PlanOptions::robust",
    Checks => "PlanOptions::checks",
    Feedback => "PlanOptions::feedback",
    CorrectionLimits => "VelocityDesign::velocity_limit/acceleration_limit",
    WeighedLoad => "ControllerFile::with_weighed_load",
    Pick => "MovePlan::candidate_named",
    EmitC => "plan::emit::emit_filter_c",
    FilterRate => "plan::emit::emit_filter_c rate_hz",
    Free => "IdentifyOptions::free",
    Noise => "IdentifyOptions::noise",
    Start => "IdentifyOptions::start",
});

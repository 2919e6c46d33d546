//! Colours, spacing and fonts, in one place, for the dark and light themes.

use eframe::egui::{self, Color32, Visuals};

/// The fonts: egui's bundled ones, with its monospace font (Hack) also a
/// fallback of the proportional text, so arrows (→) and the other symbols Hack
/// has render in labels instead of missing-glyph boxes.
pub fn fonts() -> egui::FontDefinitions {
    let mut fonts = egui::FontDefinitions::default();
    let mono = fonts
        .families
        .get(&egui::FontFamily::Monospace)
        .and_then(|f| f.first())
        .cloned();
    if let (Some(mono), Some(prop)) = (
        mono,
        fonts.families.get_mut(&egui::FontFamily::Proportional),
    ) {
        if !prop.contains(&mono) {
            prop.push(mono);
        }
    }
    fonts
}

/// The palette the views draw with.
#[derive(Clone, Copy, Debug)]
pub struct Theme {
    /// Dark or light.
    pub dark: bool,
    /// Scheduled activity bars.
    pub scheduled: Color32,
    /// The activity of the current step.
    pub current: Color32,
    /// Failed activities.
    pub failed: Color32,
    /// Skipped activities.
    pub skipped: Color32,
    /// Pending activities' windows.
    pub pending: Color32,
    /// Awake periods.
    pub awake: Color32,
    /// Wakeup and shutdown at the ends of awake periods.
    pub wake: Color32,
    /// Preheats.
    pub preheat: Color32,
    /// Maintenance heating.
    pub maintenance: Color32,
    /// Comm passes.
    pub comm: Color32,
    /// Selection outline.
    pub selection: Color32,
    /// Bar labels.
    pub label: Color32,
    /// Row labels and axes.
    pub muted: Color32,
    /// Limit lines on plots.
    pub limit: Color32,
    /// Valid intervals in the inspector.
    pub valid: Color32,
    /// The banner after an edit.
    pub banner: Color32,
    /// Error text.
    pub error: Color32,
    /// Execution: the first cycle's prediction (bars under the executed ones, the
    /// predicted profiles).
    pub predicted: Color32,
    /// Execution: activities aborted at `start + duration`.
    pub aborted: Color32,
    /// Execution: activities that never started (drawn over their prediction).
    pub not_run: Color32,
    /// Execution: the scheduling cycle markers.
    pub cycle: Color32,
    /// Flexibility: where a bar can move with every check passing and every
    /// other placement fixed (free slack), shaded behind it.
    pub slack_free: Color32,
    /// Flexibility: where it is free of temporal conflicts only (breaking
    /// energy, power, wake/sleep or heating).
    pub slack_phase1: Color32,
    /// Flexibility: the whiskers of the start bounds `[lb, ub]`.
    pub whisker: Color32,
    /// Flexibility: the outline of the selected activity's dispatchable
    /// neighbours.
    pub neighbour: Color32,
    /// Flexibility: the ghost of a dragged bar.
    pub ghost: Color32,
    /// Repair view: behind the text at the path of the error looked at.
    pub error_mark: Color32,
    /// The outline of the bars the search and filters match.
    pub highlight: Color32,
    /// What a failed activity would have caused: its profile over a plot and
    /// the violation point.
    pub would_cause: Color32,
    /// The outline of the culprits of the selected failed activity's energy or
    /// peak-power failure.
    pub culprit: Color32,
    /// The guided tour: the outline of what its page talks about.
    pub tour: Color32,
}

/// Least distance between two labelled value grid lines on a plot (points).
pub const VALUE_GRID_GAP: f32 = 24.0;
/// Size of a limit line's label on a plot.
pub const LIMIT_FONT_SIZE: f32 = 10.0;

/// Opacity of a window bar's fill (a failed, skipped, pending or never-run
/// activity's window), of its hatching, the hatch spacing and line width.
pub const WINDOW_FILL: f32 = 0.18;
/// See [`WINDOW_FILL`].
pub const WINDOW_HATCH: f32 = 0.55;
/// See [`WINDOW_FILL`].
pub const HATCH_GAP: f32 = 6.0;
/// See [`WINDOW_FILL`].
pub const HATCH_STROKE: f32 = 1.0;

/// Height of the Gantt's time ruler (points).
pub const RULER_HEIGHT: f32 = 16.0;
/// Least distance between two labelled time ticks (points).
pub const TICK_GAP: f64 = 64.0;
/// Length of a time tick on the ruler (points).
pub const TICK_LENGTH: f32 = 4.0;
/// Stroke of a sol boundary line through the Gantt rows.
pub const SOL_LINE_STROKE: f32 = 1.0;

/// Height of one Gantt lane (points).
pub const LANE_HEIGHT: f32 = 16.0;
/// Gap between lanes.
pub const LANE_GAP: f32 = 2.0;
/// Width of the row-label column.
pub const LABEL_WIDTH: f32 = 110.0;
/// Height of each plot.
pub const PLOT_HEIGHT: f32 = 120.0;
/// Width of the inspector side panel.
pub const INSPECTOR_WIDTH: f32 = 380.0;
/// Minimum bar width (points) for drawing a label inside it.
pub const LABEL_MIN_WIDTH: f32 = 40.0;
/// Width of the activity list side panel.
pub const LIST_WIDTH: f32 = 230.0;
/// The narrowest the activity list can be dragged.
pub const LIST_MIN_WIDTH: f32 = 160.0;
/// The narrowest the inspector can be dragged.
pub const INSPECTOR_MIN_WIDTH: f32 = 280.0;
/// What the side panels always leave to the Gantt and plots between them (the
/// smallest window, 900 points wide, holds all three at their narrowest).
pub const CENTRAL_MIN_WIDTH: f32 = 380.0;
/// Text size of labels inside Gantt bars and rows.
pub const BAR_FONT_SIZE: f32 = 11.0;
/// Corner radius of Gantt bars.
pub const BAR_ROUNDING: f32 = 2.0;
/// Outline width of the bar of the current step's activity.
pub const CURRENT_STROKE: f32 = 2.0;
/// Outline width of the selected activity's bar.
pub const SELECTION_STROKE: f32 = 1.5;
/// Width of the Gantt's line at the time probed on the plots.
pub const PROBE_LINE_STROKE: f32 = 1.0;
/// Width of the base line of a valid-intervals track.
pub const TRACK_LINE_STROKE: f32 = 0.5;
/// Height of one row of the inspector's valid-intervals tracks.
pub const TRACK_ROW_HEIGHT: f32 = 10.0;
/// Gap between two tracks.
pub const TRACK_ROW_GAP: f32 = 3.0;
/// Text size of the track labels.
pub const TRACK_FONT_SIZE: f32 = 9.0;
/// Width of an editor text field in the inspector.
pub const FIELD_WIDTH: f32 = 200.0;
/// Outline width of the bars the search and filters match.
pub const MATCH_STROKE: f32 = 1.5;
/// Opacity of the bars the search and filters leave out.
pub const DIMMED: f32 = 0.2;
/// Width of each time range field.
pub const RANGE_FIELD_WIDTH: f32 = 120.0;
/// Inner margin of the banner and error frames.
pub const MESSAGE_MARGIN: f32 = 4.0;
/// The largest share of the Gantt-and-plots area the change banner's text
/// covers; a longer summary scrolls inside it, so the chart stays in view.
pub const BANNER_MAX_SHARE: f32 = 0.25;
/// Height of the thin predicted bar under an executed one (execution mode).
pub const BASELINE_HEIGHT: f32 = 5.0;
/// Smallest width of a marker on the Gantt (cycles, violations), so it can be
/// seen and hovered at any zoom.
pub const MARKER_WIDTH: f32 = 3.0;
/// Width of the line at the looked-at cycle's time (Gantt and plots).
pub const CYCLE_LINE_STROKE: f32 = 1.5;
/// Width of the seed field.
pub const SEED_FIELD_WIDTH: f32 = 60.0;
/// Width of the cycle slider.
pub const CYCLE_SLIDER_WIDTH: f32 = 240.0;
/// Width of the typed-path prompt (no file dialog service).
pub const PROMPT_WIDTH: f32 = 480.0;
/// Width of the step slider's rail.
pub const STEP_SLIDER_WIDTH: f32 = 320.0;
/// The least room left beside the step slider for the step's label to stay on
/// the slider's line (cut with an ellipsis there) rather than wrap below it.
pub const STEP_LABEL_MIN_WIDTH: f32 = 160.0;
/// The fewest rail points per step the step slider gives before it offers to
/// zoom (a longer run gets "Zoom steps in" / "Zoom steps out"), and the
/// fewest a planner can pick one step at with the mouse.
pub const STEP_PICK_POINTS: f32 = 4.0;
/// Height of a failure tick on the step slider.
pub const FAILURE_TICK_HEIGHT: f32 = 5.0;
/// Width of a failure tick on the step slider.
pub const FAILURE_TICK_STROKE: f32 = 1.5;
/// Width of the Monte Carlo panel's runs and seed fields.
pub const CAMPAIGN_FIELD_WIDTH: f32 = 60.0;
/// Height of a Monte Carlo histogram (lowest and handover state of charge).
pub const HISTOGRAM_HEIGHT: f32 = 90.0;
/// Size of the completed / aborted / not-run bar in the activity list.
pub const SHARE_BAR_WIDTH: f32 = 36.0;
/// Height of that bar.
pub const SHARE_BAR_HEIGHT: f32 = 8.0;
/// Height of the larger bar in the inspector.
pub const SHARE_BAR_LARGE_HEIGHT: f32 = 14.0;
/// Narrowest part of a share bar (points), so that a few runs still show.
pub const SHARE_MIN_WIDTH: f32 = 1.0;
/// Outline width of share bars and histogram bars.
pub const BAR_OUTLINE_STROKE: f32 = 1.0;
/// Width of a limit's line on a histogram.
pub const LIMIT_LINE_STROKE: f32 = 1.5;
/// Width of the slack whiskers on the Gantt.
pub const WHISKER_STROKE: f32 = 1.0;
/// Height of the ticks at the ends of a whisker (points: the same at every zoom).
pub const WHISKER_TICK: f32 = 8.0;
/// A slack whisker reaching less than this (points) past its bar on both sides
/// is not drawn: it would not show beside the bar (at a whole-plan zoom of
/// 10,000 activities, thousands of them cost a frame more than the bars).
pub const WHISKER_MIN_REACH: f32 = 1.0;
/// Outline width of the culprits' bars of the selected failed activity.
pub const CULPRIT_STROKE: f32 = 2.0;
/// Width of the line of what a failed activity would have caused on a plot.
pub const WOULD_CAUSE_STROKE: f32 = 1.5;
/// Radius of the violation point's marker on a plot.
pub const VIOLATION_RADIUS: f32 = 4.0;
/// Width of the guided tour's window.
pub const TOUR_WIDTH: f32 = 340.0;
/// Gap between the guided tour's window and what it points at.
pub const TOUR_GAP: f32 = 12.0;
/// Height of the inspector section the guided tour outlines when no heading
/// follows it (points).
pub const TOUR_SECTION: f32 = 240.0;
/// Outline width of what the guided tour's page talks about.
pub const TOUR_OUTLINE: f32 = 2.0;
/// Corner radius of the guided tour's outline.
pub const TOUR_OUTLINE_ROUNDING: f32 = 4.0;
/// Room left between an outlined inspector section and the heading after it.
pub const TOUR_SECTION_GAP: f32 = 2.0;
/// Radius of the hollow markers of the other reasons' violations.
pub const OTHER_VIOLATION_RADIUS: f32 = 3.5;
/// Outline width of the selected activity's dispatchable neighbours.
pub const NEIGHBOUR_STROKE: f32 = 1.5;
/// Outline width of the ghost of a dragged bar.
pub const GHOST_STROKE: f32 = 1.5;
/// Repair view: default width of the list of errors.
pub const REPAIR_LIST_WIDTH: f32 = 420.0;
/// Repair view: most height of the value field before it scrolls.
pub const REPAIR_VALUE_HEIGHT: f32 = 160.0;
/// Repair view: most ids listed to pick from at once (typing narrows them).
pub const REPAIR_PICK_SHOWN: usize = 200;
/// Editor: width of a field holding a sol and local time.
pub const TIME_FIELD_WIDTH: f32 = 118.0;
/// Editor: width of the combo boxes of a state requirement or effect.
pub const COMBO_WIDTH: f32 = 82.0;
/// Editor: width of a field holding a number.
pub const NUMBER_FIELD_WIDTH: f32 = 90.0;
/// Editor: width of the search field and list of the activity picker.
pub const PICKER_WIDTH: f32 = 240.0;
/// Editor: most height of the activity picker's list.
pub const PICKER_HEIGHT: f32 = 220.0;

impl Theme {
    /// The palette for dark or light mode.
    pub fn new(dark: bool) -> Self {
        if dark {
            Self {
                dark,
                scheduled: Color32::from_rgb(70, 130, 200),
                current: Color32::from_rgb(255, 190, 60),
                failed: Color32::from_rgb(220, 80, 70),
                skipped: Color32::from_rgb(150, 110, 170),
                pending: Color32::from_rgba_unmultiplied(160, 160, 160, 60),
                awake: Color32::from_rgb(90, 170, 110),
                wake: Color32::from_rgb(50, 110, 70),
                preheat: Color32::from_rgb(230, 120, 50),
                maintenance: Color32::from_rgb(190, 100, 60),
                comm: Color32::from_rgb(60, 190, 200),
                selection: Color32::WHITE,
                label: Color32::WHITE,
                muted: Color32::from_gray(160),
                limit: Color32::from_rgb(220, 80, 70),
                valid: Color32::from_rgb(90, 170, 110),
                banner: Color32::from_rgb(40, 60, 90),
                error: Color32::from_rgb(255, 110, 100),
                predicted: Color32::from_rgb(150, 165, 190),
                aborted: Color32::from_rgb(200, 90, 200),
                not_run: Color32::from_rgba_unmultiplied(220, 80, 70, 90),
                cycle: Color32::from_gray(130),
                slack_free: Color32::from_rgba_unmultiplied(90, 190, 120, 85),
                slack_phase1: Color32::from_rgba_unmultiplied(235, 170, 50, 80),
                whisker: Color32::from_gray(200),
                neighbour: Color32::from_rgb(255, 120, 210),
                ghost: Color32::from_rgba_unmultiplied(255, 255, 255, 40),
                error_mark: Color32::from_rgba_unmultiplied(255, 110, 100, 70),
                highlight: Color32::from_rgb(200, 255, 80),
                would_cause: Color32::from_rgba_unmultiplied(255, 170, 60, 200),
                culprit: Color32::from_rgb(255, 170, 60),
                tour: Color32::from_rgb(120, 200, 255),
            }
        } else {
            Self {
                dark,
                scheduled: Color32::from_rgb(60, 110, 190),
                current: Color32::from_rgb(230, 150, 0),
                failed: Color32::from_rgb(200, 50, 40),
                skipped: Color32::from_rgb(130, 90, 160),
                pending: Color32::from_rgba_unmultiplied(90, 90, 90, 50),
                awake: Color32::from_rgb(60, 150, 80),
                wake: Color32::from_rgb(30, 100, 50),
                preheat: Color32::from_rgb(220, 100, 30),
                maintenance: Color32::from_rgb(170, 80, 40),
                comm: Color32::from_rgb(20, 150, 170),
                selection: Color32::BLACK,
                label: Color32::WHITE,
                muted: Color32::from_gray(90),
                limit: Color32::from_rgb(200, 50, 40),
                valid: Color32::from_rgb(60, 150, 80),
                banner: Color32::from_rgb(220, 230, 245),
                error: Color32::from_rgb(190, 30, 20),
                predicted: Color32::from_rgb(110, 125, 155),
                aborted: Color32::from_rgb(170, 50, 170),
                not_run: Color32::from_rgba_unmultiplied(200, 50, 40, 80),
                cycle: Color32::from_gray(120),
                slack_free: Color32::from_rgba_unmultiplied(50, 150, 80, 60),
                slack_phase1: Color32::from_rgba_unmultiplied(220, 140, 20, 60),
                whisker: Color32::from_gray(60),
                neighbour: Color32::from_rgb(200, 40, 150),
                ghost: Color32::from_rgba_unmultiplied(0, 0, 0, 35),
                error_mark: Color32::from_rgba_unmultiplied(190, 30, 20, 50),
                highlight: Color32::from_rgb(20, 140, 20),
                would_cause: Color32::from_rgba_unmultiplied(210, 110, 0, 210),
                culprit: Color32::from_rgb(210, 110, 0),
                tour: Color32::from_rgb(0, 110, 200),
            }
        }
    }

    /// egui's visuals for this theme.
    pub fn visuals(&self) -> Visuals {
        if self.dark {
            Visuals::dark()
        } else {
            Visuals::light()
        }
    }
}

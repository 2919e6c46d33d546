//! The keyboard: every [`UiCommand`] with a shortcut, mapped to egui's
//! (`kb_shortcut`), and the keys pressed in a frame turned into those commands
//! ([`keys`]), going through [`UiCommand::ALL`], so a command with a shortcut
//! cannot be left out of the keyboard handling.

use eframe::egui;

use crate::state::{Command, Key, Modifiers, Shortcut, UiCommand};

/// egui's key for `key`.
fn egui_key(key: Key) -> egui::Key {
    match key {
        Key::O => egui::Key::O,
        Key::S => egui::Key::S,
        Key::Z => egui::Key::Z,
        Key::F => egui::Key::F,
        Key::T => egui::Key::T,
        Key::Num1 => egui::Key::Num1,
        Key::Num2 => egui::Key::Num2,
        Key::Home => egui::Key::Home,
        Key::End => egui::Key::End,
        Key::PageUp => egui::Key::PageUp,
        Key::PageDown => egui::Key::PageDown,
        Key::ArrowLeft => egui::Key::ArrowLeft,
        Key::ArrowRight => egui::Key::ArrowRight,
        Key::ArrowUp => egui::Key::ArrowUp,
        Key::ArrowDown => egui::Key::ArrowDown,
        Key::F3 => egui::Key::F3,
    }
}

/// egui's modifiers for `m` (`command` is Ctrl, or Cmd on a Mac).
fn egui_modifiers(m: Modifiers) -> egui::Modifiers {
    let mut out = if m.command {
        egui::Modifiers::COMMAND
    } else {
        egui::Modifiers::NONE
    };
    out.shift = m.shift;
    out.alt = m.alt;
    out
}

/// egui's shortcut for `s`.
pub fn egui_shortcut(s: Shortcut) -> egui::KeyboardShortcut {
    egui::KeyboardShortcut::new(egui_modifiers(s.modifiers), egui_key(s.key))
}

/// The keyboard shortcut of `cmd`, if it has one, as egui's.
pub fn kb_shortcut(cmd: UiCommand) -> Option<egui::KeyboardShortcut> {
    cmd.shortcut().map(egui_shortcut)
}

/// Keyboard: the commands whose shortcut was pressed this frame. Those taken
/// while typing ([`Shortcut::while_typing`]: undo/redo, save/open, search)
/// once per frame each, in the order of [`UiCommand::ALL`]; the others
/// (stepping, the list, Back and Forward) only when no text field has focus,
/// every press counting.
pub fn keys(ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
    let with = |typing: bool| {
        UiCommand::ALL.iter().filter_map(move |&cmd| {
            let s = cmd.shortcut()?;
            (s.while_typing() == typing).then_some((cmd, egui_shortcut(s)))
        })
    };
    let mut undo_redo = false;
    for (cmd, shortcut) in with(true) {
        // One of undo and redo per frame (redo is checked first).
        let is_undo_redo = matches!(cmd, UiCommand::Undo | UiCommand::Redo);
        if is_undo_redo && undo_redo {
            continue;
        }
        if ui.input_mut(|i| i.consume_shortcut(&shortcut)) {
            undo_redo |= is_undo_redo;
            cmds.push(cmd.into());
        }
    }
    // After Ctrl+F the keys are the search field's (focused before it is
    // drawn this frame), not shortcuts.
    let searching = cmds.contains(&UiCommand::Search.into());
    if searching || ui.ctx().egui_wants_keyboard_input() {
        return;
    }
    for (cmd, shortcut) in with(false) {
        // Every press counts: five quick presses between two frames are five
        // steps (key repeats too).
        for _ in 0..ui.input(|i| presses(i, shortcut)) {
            cmds.push(cmd.into());
        }
    }
}

/// How many times `shortcut` was pressed this frame, with exactly its modifiers
/// (Shift+Right is not also Right).
fn presses(input: &egui::InputState, shortcut: egui::KeyboardShortcut) -> usize {
    input
        .events
        .iter()
        .filter(|e| {
            matches!(e, egui::Event::Key { key, pressed: true, modifiers, .. }
                if *key == shortcut.logical_key && modifiers.matches_exact(shortcut.modifiers))
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The commands `keys` gives in one frame where `shortcut` is pressed once
    /// (no text field has focus).
    fn given_by(shortcut: egui::KeyboardShortcut) -> Vec<Command> {
        let ctx = egui::Context::default();
        let key = |pressed| egui::Event::Key {
            key: shortcut.logical_key,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: shortcut.modifiers,
        };
        let input = egui::RawInput {
            events: vec![key(true), key(false)],
            ..Default::default()
        };
        let mut cmds = Vec::new();
        let mut out = ctx.run_ui(input, |ui| keys(ui, &mut cmds));
        // Nothing draws the frame's textures here.
        out.textures_delta.clear();
        cmds
    }

    #[test]
    fn no_two_commands_share_a_shortcut() {
        let with: Vec<(UiCommand, Shortcut)> = UiCommand::ALL
            .iter()
            .filter_map(|&c| c.shortcut().map(|s| (c, s)))
            .collect();
        assert!(with.len() >= 20, "{with:?}");
        for (i, (a, sa)) in with.iter().enumerate() {
            for (b, sb) in &with[i + 1..] {
                assert_ne!(sa, sb, "{a:?} and {b:?} share a shortcut");
                assert_ne!(
                    egui_shortcut(*sa),
                    egui_shortcut(*sb),
                    "{a:?} and {b:?} share egui's shortcut"
                );
            }
        }
    }

    #[test]
    fn every_command_with_a_shortcut_is_given_by_its_key_alone() {
        for &cmd in UiCommand::ALL {
            let Some(shortcut) = kb_shortcut(cmd) else {
                continue;
            };
            assert_eq!(
                given_by(shortcut),
                [Command::Ui(cmd)],
                "{cmd:?} on {shortcut:?}"
            );
        }
    }

    #[test]
    fn a_plain_key_counts_every_press_and_a_typing_one_once() {
        let right = kb_shortcut(UiCommand::NextStep).expect("a key");
        let ctx = egui::Context::default();
        let press = |key, modifiers| egui::Event::Key {
            key,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers,
        };
        let undo = kb_shortcut(UiCommand::Undo).expect("a key");
        let input = egui::RawInput {
            events: vec![
                press(right.logical_key, right.modifiers),
                press(right.logical_key, right.modifiers),
                press(right.logical_key, egui::Modifiers::SHIFT),
                press(undo.logical_key, undo.modifiers),
                press(undo.logical_key, undo.modifiers),
            ],
            ..Default::default()
        };
        let mut cmds = Vec::new();
        let mut out = ctx.run_ui(input, |ui| keys(ui, &mut cmds));
        // Nothing draws the frame's textures here.
        out.textures_delta.clear();
        assert_eq!(
            cmds,
            [
                UiCommand::Undo.into(),
                UiCommand::NextStep.into(),
                UiCommand::NextStep.into(),
                UiCommand::NextFailure.into(),
            ]
        );
    }
}

//! The variants in the side panel: a drop-down per variant set that picks the choice the
//! preview renders (not saved: the file's default changes only in the editor), the variant
//! sets' editor ([`VARIANTS_PANEL`]), and a `switch` node's inspector. Every edit goes
//! through [`super::variants`].

use super::state::EditorState;
use super::variants::{self, VARIANTS_PANEL};
use egui::{Color32, Ui};

/// Red of the messages the panels show.
const ERROR: Color32 = Color32::from_rgb(255, 120, 110);

/// The previewed choice of each variant set, as drop-downs (the set's doc on hover of its
/// name). Shown only where the graph declares a set; a click on the heading opens the
/// editor. Picking a choice re-renders the preview at it; the file is unchanged.
pub fn variants_panel(ui: &mut Ui, state: &mut EditorState) -> bool {
    let sets = state.doc.doc().variants.clone();
    if sets.is_empty() {
        return false;
    }
    let heading = ui
        .add(egui::Label::new(egui::RichText::new("Variants").strong()).sense(egui::Sense::click()))
        .on_hover_text(
            "the choice the preview shows (not saved); click to edit the variant sets and their defaults",
        );
    if heading.clicked() {
        state.focus = Some(VARIANTS_PANEL.to_owned());
    }
    let mut picked = None;
    egui::Grid::new("matgraph-variants")
        .num_columns(2)
        .show(ui, |ui| {
            for (set, v) in &sets {
                let current = state
                    .preview
                    .variant(set)
                    .filter(|c| v.choices.iter().any(|x| x == c))
                    .unwrap_or(&v.default)
                    .to_owned();
                let label = ui.label(set);
                if !v.doc.is_empty() {
                    label.on_hover_text(&v.doc);
                }
                egui::ComboBox::from_id_salt(("matgraph-variant-pick", set))
                    .selected_text(choice_text(&current, &v.default))
                    .show_ui(ui, |ui| {
                        for c in &v.choices {
                            if ui
                                .selectable_label(*c == current, choice_text(c, &v.default))
                                .clicked()
                                && *c != current
                            {
                                picked = Some((set.clone(), c.clone(), v.default.clone()));
                            }
                        }
                    });
                ui.end_row();
            }
        });
    if let Some((set, choice, default)) = picked {
        pick(state, &set, &choice, &default);
    }
    true
}

/// A choice as the drop-downs write it: `exact (default)` for the file's default.
pub fn choice_text(choice: &str, default: &str) -> String {
    match choice == default {
        true => format!("{choice} (default)"),
        false => choice.to_owned(),
    }
}

/// Previews set `set` at `choice` (its file default `default`); the status line says so.
pub fn pick(state: &mut EditorState, set: &str, choice: &str, default: &str) {
    state.preview.set_variant(set, Some(choice));
    state.status = Some(format!(
        "the preview shows {set} = {choice} (the file's default stays '{default}')"
    ));
}

/// What the variants editor was asked for this frame.
enum Op {
    RenameSet(String, String),
    Doc(String, String),
    RemoveSet(String),
    AddSwitch(String),
    RenameChoice(String, String, String),
    RemoveChoice(String, String),
    MoveChoice(String, String, bool),
    Default(String, String),
    AddChoice(String, String),
    AddSet(String, String),
}

/// The variant sets' editor (the side panel, a click on the Variants heading, or Edit →
/// Variant sets…): each set's name, doc and choices (rename by typing and Enter; the
/// default; up, down; ×), a switch added for it at `centre` (canvas), the set deleted; and
/// a new set declared.
pub fn variants_editor(ui: &mut Ui, state: &mut EditorState, centre: [f32; 2]) {
    ui.heading("Variant sets");
    ui.label(
        "Alternative implementations the graph chooses between at compile time: a switch \
         node passes on the input of its set's choice. The default is what the file renders; \
         the drop-downs under the preview only preview a choice.",
    );
    ui.separator();
    let sets = state.doc.doc().variants.clone();
    let mut op = None;
    let field = |k: usize, what: &str, j: usize| {
        egui::Id::new("matgraph-variant-field")
            .with(k)
            .with(what)
            .with(j)
    };
    let text = |ui: &mut Ui, id: egui::Id, now: &str| {
        ui.data_mut(|d| d.get_temp::<String>(id).unwrap_or(now.to_owned()))
    };
    let mut fields = 0;
    for (k, (set, v)) in sets.iter().enumerate() {
        let name_id = field(k, "name", 0);
        let mut name = text(ui, name_id, set);
        ui.horizontal(|ui| {
            let edit = ui.add(egui::TextEdit::singleline(&mut name).desired_width(110.0));
            if edit.lost_focus() && name != *set {
                op = Some(Op::RenameSet(set.clone(), name.clone()));
            }
            if ui
                .button("add switch")
                .on_hover_text(format!(
                    "a switch node bound to '{set}', one input per choice, in the middle of the view"
                ))
                .clicked()
            {
                op = Some(Op::AddSwitch(set.clone()));
            }
            if ui
                .small_button("×")
                .on_hover_text(format!(
                    "delete '{set}': each switch bound to it is replaced by its default choice's wire"
                ))
                .clicked()
            {
                op = Some(Op::RemoveSet(set.clone()));
            }
        });
        ui.data_mut(|d| d.insert_temp(name_id, name));
        let doc_id = field(k, "doc", 0);
        let mut doc = text(ui, doc_id, &v.doc);
        let edit = ui.add(
            egui::TextEdit::multiline(&mut doc)
                .hint_text("doc: what the choices trade")
                .desired_rows(1)
                .desired_width(f32::INFINITY),
        );
        if edit.lost_focus() && doc != v.doc {
            op = Some(Op::Doc(set.clone(), doc.clone()));
        }
        ui.data_mut(|d| d.insert_temp(doc_id, doc));
        for (j, c) in v.choices.iter().enumerate() {
            let choice_id = field(k, "choice", j);
            let mut choice = text(ui, choice_id, c);
            ui.horizontal(|ui| {
                ui.add_space(12.0);
                let edit = ui.add(egui::TextEdit::singleline(&mut choice).desired_width(90.0));
                if edit.lost_focus() && choice != *c {
                    op = Some(Op::RenameChoice(set.clone(), c.clone(), choice.clone()));
                }
                if ui
                    .radio(v.default == *c, "default")
                    .on_hover_text(format!("the file renders '{set}' as '{c}'"))
                    .clicked()
                    && v.default != *c
                {
                    op = Some(Op::Default(set.clone(), c.clone()));
                }
                if ui
                    .add_enabled(j > 0, egui::Button::new("up").small())
                    .on_hover_text(format!("move '{c}' up"))
                    .clicked()
                {
                    op = Some(Op::MoveChoice(set.clone(), c.clone(), true));
                }
                if ui
                    .add_enabled(j + 1 < v.choices.len(), egui::Button::new("down").small())
                    .on_hover_text(format!("move '{c}' down"))
                    .clicked()
                {
                    op = Some(Op::MoveChoice(set.clone(), c.clone(), false));
                }
                if ui
                    .add_enabled(v.choices.len() > 1, egui::Button::new("×").small())
                    .on_hover_text(format!("remove choice '{c}' (the switches drop its input)"))
                    .clicked()
                {
                    op = Some(Op::RemoveChoice(set.clone(), c.clone()));
                }
            });
            ui.data_mut(|d| d.insert_temp(choice_id, choice));
            fields = fields.max(j + 1);
        }
        let new_id = field(k, "new-choice", 0);
        let mut new_choice = text(ui, new_id, "");
        ui.horizontal(|ui| {
            ui.add_space(12.0);
            ui.add(
                egui::TextEdit::singleline(&mut new_choice)
                    .hint_text("choice")
                    .desired_width(90.0),
            );
            if ui
                .button("add choice")
                .on_hover_text(
                    "each switch bound to the set gets an input for it, wired as the default's",
                )
                .clicked()
            {
                op = Some(Op::AddChoice(set.clone(), new_choice.clone()));
            }
        });
        ui.data_mut(|d| d.insert_temp(new_id, new_choice));
        let switches = variants::switches_of(state.doc.doc(), set);
        ui.weak(match switches.is_empty() {
            true => "no switch follows it yet".to_owned(),
            false => format!("switches: {}", switches.join(", ")),
        });
        ui.separator();
    }
    let set_id = egui::Id::new("matgraph-variant-add-name");
    let choices_id = egui::Id::new("matgraph-variant-add-choices");
    let mut new_set = text(ui, set_id, "");
    let mut new_choices = text(ui, choices_id, "");
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut new_set)
                .hint_text("set name")
                .desired_width(90.0),
        );
        ui.add(
            egui::TextEdit::singleline(&mut new_choices)
                .hint_text("choices: a b")
                .desired_width(110.0),
        );
    });
    if ui
        .button("add variant set")
        .on_hover_text(
            "choices separated by spaces or commas (default: a b); the first is the default",
        )
        .clicked()
    {
        op = Some(Op::AddSet(new_set.clone(), new_choices.clone()));
    }
    ui.data_mut(|d| {
        d.insert_temp(set_id, new_set);
        d.insert_temp(choices_id, new_choices);
    });
    let Some(op) = op else { return };
    // Refused edits (a bad or taken name) leave the reason in the status line.
    let done = match op {
        Op::RenameSet(old, new) => state.rename_variant_set(&old, &new).is_ok(),
        Op::Doc(set, doc) => state.set_variant_doc(&set, &doc).is_ok(),
        Op::RemoveSet(set) => state.remove_variant_set(&set).is_ok(),
        Op::AddSwitch(set) => state.add_switch(&set, centre).is_ok(),
        Op::RenameChoice(set, old, new) => state.rename_variant_choice(&set, &old, &new).is_ok(),
        Op::RemoveChoice(set, c) => state.remove_variant_choice(&set, &c).is_ok(),
        Op::MoveChoice(set, c, up) => state.move_variant_choice(&set, &c, up).is_ok(),
        Op::Default(set, c) => state.set_variant_default(&set, &c).is_ok(),
        Op::AddChoice(set, c) => {
            let name = Some(c.trim()).filter(|c| !c.is_empty());
            state.add_variant_choice(&set, name).is_ok()
        }
        Op::AddSet(name, choices) => {
            let choices: Vec<&str> = choices
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|c| !c.is_empty())
                .collect();
            let name = Some(name.trim()).filter(|n| !n.is_empty());
            state.add_variant_set(name, &choices).is_ok()
        }
    };
    // The fields show the document again (a refused name goes back to the one written; a
    // set or choice added clears its field).
    ui.data_mut(|d| {
        for k in 0..=sets.len() {
            for what in ["name", "doc", "new-choice"] {
                d.remove::<String>(field(k, what, 0));
            }
            for j in 0..fields {
                d.remove::<String>(field(k, "choice", j));
            }
        }
        if done {
            d.remove::<String>(set_id);
            d.remove::<String>(choices_id);
        }
    });
}

/// The side panel of `switch` node `id`: the set it follows (another can be picked), what
/// each choice's input reads, the previewed choice, another switch for the set added at
/// `centre` (canvas), and the variants editor.
pub fn switch_inspector(ui: &mut Ui, state: &mut EditorState, id: &str, centre: [f32; 2]) {
    let Some(node) = state.doc.node(id).cloned() else {
        return;
    };
    ui.heading(id);
    let bound = node.variant.clone().unwrap_or_default();
    let sets = state.doc.doc().variants.clone();
    let mut rebind = None;
    ui.horizontal(|ui| {
        ui.label("switch · variant set");
        egui::ComboBox::from_id_salt("matgraph-switch-set")
            .selected_text(if bound.is_empty() { "none" } else { &bound })
            .show_ui(ui, |ui| {
                for s in sets.keys() {
                    if ui.selectable_label(*s == bound, s).clicked() && *s != bound {
                        rebind = Some(s.clone());
                    }
                }
            });
    });
    for e in state.doc.node_errors(id) {
        ui.colored_label(ERROR, e);
    }
    let mut add = false;
    if let Some(v) = sets.get(&bound) {
        if !v.doc.is_empty() {
            ui.label(&v.doc);
        }
        let current = state
            .preview
            .variant(&bound)
            .filter(|c| v.choices.iter().any(|x| x == c))
            .unwrap_or(&v.default)
            .to_owned();
        for c in &v.choices {
            let shown = if *c == current { "▶ " } else { "" };
            match state.doc.link(id, c) {
                Some(l) => ui.label(format!("{shown}{} ← {l}", choice_text(c, &v.default))),
                None => ui.colored_label(
                    ERROR,
                    format!("{shown}{}: unwired", choice_text(c, &v.default)),
                ),
            };
        }
        ui.weak("▶ the choice the preview shows (the drop-downs under the preview)");
        add = ui
            .button("add another switch")
            .on_hover_text(format!("a new switch bound to '{bound}'"))
            .clicked();
    } else if !bound.is_empty() {
        ui.colored_label(ERROR, format!("variant set '{bound}' is not declared"));
    }
    if ui.button("Edit variant sets").clicked() {
        state.focus = Some(VARIANTS_PANEL.to_owned());
    }
    if add {
        let _ = state.add_switch(&bound, centre);
    }
    if let Some(set) = rebind {
        let _ = state.bind_switch(id, &set);
    }
}

//! The canvas viewer (egui-snarl's [`SnarlViewer`]): node headers coloured by category, pins
//! by socket type (generic pins square), values edited in place. It only reads the document
//! and queues [`Action`]s, which the app applies after the frame through the state's edits.

use super::cull::Culling;
use super::layout::HEADER_HEIGHT;
use super::model::EditorDoc;
use super::overview::{Body, Overview, pin_shape};
use super::search::WireFilter;
use super::view::{GENERIC_UNKNOWN, NodeView, category_color, socket_color};
use super::widgets::{current_lanes, port_hover, value_editor};
use crate::node::PortType;
use egui::{Color32, Shape, Stroke, Ui};
use egui_snarl::ui::{AnyPins, BackgroundPattern, PinInfo, PinShape, SnarlStyle, SnarlViewer};
use egui_snarl::{InPin, NodeId, OutPin, Snarl};

/// What the user asked for on the canvas during a frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Link an output to an input.
    Connect {
        /// Source node id.
        from: String,
        /// Source output name.
        output: String,
        /// Target node id.
        to: String,
        /// Target input name.
        input: String,
    },
    /// Remove the link of an input.
    Disconnect {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
    },
    /// Write a literal on an input (coalesced per input while the pointer is held).
    SetInput {
        /// Node id.
        node: String,
        /// Input name.
        input: String,
        /// The literal.
        value: serde_json::Value,
    },
    /// Open the add-node search at a canvas position, for a wire dropped there.
    Search {
        /// Canvas position.
        pos: [f32; 2],
        /// The dropped wire: its node id, port name, and what the new node must offer.
        wire: Option<(String, String, WireFilter)>,
    },
    /// Show this node in the side panel.
    Focus(String),
    /// Delete these nodes.
    Remove(Vec<String>),
    /// Duplicate these nodes.
    Duplicate(Vec<String>),
    /// Turn this node's preview swatch on or off.
    TogglePreview(String),
}

/// What a node's preview swatch shows under its pins.
#[derive(Clone, Debug, PartialEq)]
pub enum Swatch {
    /// The rendered swatch.
    Image(egui::TextureId),
    /// Why it could not be rendered.
    Message(String),
    /// Not rendered yet.
    Pending,
}

/// Side of a node's swatch on the canvas, points (before the canvas zoom).
pub const NODE_SWATCH_POINTS: f32 = 96.0;

/// Below this canvas zoom the canvas is an overview ([`super::overview`]), as Unreal's
/// graph editor drops detail when zoomed out: the pins' names and value editors would be
/// under 4 px, and laying out the widgets of every node and pin was most of the frame of a
/// large graph framed whole (benches/editor.rs). The headers (the node's id and its error
/// mark, painted without widgets; not the preview toggle) stay, and the pins and wires are
/// painted; wires are made and removed zoomed in.
pub const LOW_DETAIL_ZOOM: f32 = 0.3;

/// Canvas points between a node's estimated width ([`super::layout::node_size`]) and its overview body's:
/// the node frame's margins and the spacing beside the body.
const BODY_INSET: f32 = 16.0;

/// The viewer of one frame.
pub struct Viewer<'a> {
    /// The document (read only).
    pub doc: &'a EditorDoc,
    /// Whether sliders span the hard range (Ctrl held).
    pub hard: bool,
    /// The actions queued this frame.
    pub actions: Vec<Action>,
    /// The canvas → screen transform snarl used this frame.
    pub to_screen: Option<egui::emath::TSTransform>,
    /// The shader generator's error (naga's, mapped to a node) and its node.
    pub shader_error: Option<(String, String)>,
    /// A transform to impose this frame (frame all), canvas → screen.
    pub set_transform: Option<egui::emath::TSTransform>,
    /// The swatches of the nodes whose preview is on, by node id.
    pub swatches: std::collections::BTreeMap<String, Swatch>,
    /// The overview's pins and wires, when this frame's zoom is under [`LOW_DETAIL_ZOOM`].
    pub overview: Overview,
    /// The canvas' rect on screen (the nodes away from it are culled).
    pub canvas: egui::Rect,
    /// This frame's culling ([`super::cull`]), made once the transform is known.
    pub culling: Culling,
}

impl Viewer<'_> {
    /// The loader's errors at node `id`, and the shader generator's when it names `id`.
    fn errors_of(&self, id: &str) -> Vec<String> {
        let mut errors = self.doc.node_errors(id);
        if let Some((node, message)) = &self.shader_error
            && node == id
        {
            errors.push(message.clone());
        }
        errors
    }

    fn id<'s>(&self, snarl: &'s Snarl<NodeView>, node: NodeId) -> &'s str {
        &snarl[node].id
    }

    /// Whether the node with id `id` is culled this frame.
    fn culled(&self, id: &str) -> bool {
        self.doc
            .index(id)
            .is_some_and(|k| self.culling.is_culled(k))
    }

    /// The culling of a frame drawn with `to_screen`: each node's estimated rect against
    /// the canvas' viewport (nothing is culled before the canvas' rect is known).
    fn cull(&self, to_screen: egui::emath::TSTransform, snarl: &Snarl<NodeView>) -> Culling {
        if !self.canvas.is_positive() {
            return Culling::default();
        }
        let viewport = to_screen.inverse() * self.canvas;
        let nodes = snarl.nodes_pos_ids().filter_map(|(_, pos, view)| {
            let k = self.doc.index(&view.id)?;
            let (w, h) = *self.doc.node_sizes().get(k)?;
            Some((k, egui::Rect::from_min_size(pos, egui::vec2(w, h))))
        });
        let index = |n: NodeId| snarl.get_node(n).and_then(|v| self.doc.index(&v.id));
        let wires = snarl.wires().filter_map(|(from, to)| {
            Some((index(from.node)?, from.output, index(to.node)?, to.input))
        });
        Culling::new(viewport, self.doc.doc().nodes.len(), nodes, wires)
    }

    /// How many of a node's `all` input or output pins egui-snarl draws this frame: none in
    /// the overview (it paints them, `show_body`), else those `culled` leaves.
    fn pins_shown(
        &self,
        node: &NodeView,
        all: usize,
        culled: fn(&Culling, usize, usize) -> usize,
    ) -> usize {
        if self.low_detail() {
            return 0;
        }
        self.doc
            .index(&node.id)
            .map_or(all, |k| culled(&self.culling, k, all))
    }

    /// `frame` as this frame draws it: [`plain`] in the overview.
    fn frame_for_zoom(&self, frame: egui::Frame) -> egui::Frame {
        match self.low_detail() {
            true => plain(frame),
            false => frame,
        }
    }

    /// Whether this frame's zoom is under [`LOW_DETAIL_ZOOM`].
    fn low_detail(&self) -> bool {
        self.to_screen.is_some_and(|t| t.scaling < LOW_DETAIL_ZOOM)
    }

    /// A pin's colour (its socket type's) and shape (square for a generic port).
    fn pin_look(&self, node: &str, port: PortType) -> (Color32, PinShape) {
        match (self.doc.port_type(node, port), port) {
            (Some(t), PortType::Fixed(_)) => (socket_color(t), PinShape::Circle),
            (Some(t), PortType::Generic) => (socket_color(t), PinShape::Square),
            (None, _) => (GENERIC_UNKNOWN, PinShape::Square),
        }
    }

    fn pin(&self, node: &str, port: PortType) -> PinInfo {
        let (fill, shape) = self.pin_look(node, port);
        PinInfo::default()
            .with_shape(shape)
            .with_fill(fill)
            .with_wire_color(fill)
    }

    /// Paints the overview's wires once the canvas drew its nodes (see [`super::overview`]),
    /// each in the mean of its ends' colours as egui-snarl mixes them, at least a pixel
    /// wide. `style` is the egui style the canvas drew with.
    pub fn paint_overview(&self, snarl: &Snarl<NodeView>, style: &egui::Style) {
        let Some(scale) = self
            .to_screen
            .map(|t| t.scaling)
            .filter(|_| self.low_detail())
        else {
            return;
        };
        let pin = style.spacing.interact_size.y * 0.6;
        let width = (pin * 0.1).max(1.0 / scale);
        let wires = snarl.wires().filter_map(|(from, to)| {
            let (a, b) = (&snarl.get_node(from.node)?.id, &snarl.get_node(to.node)?.id);
            let out = self.doc.node_type(a)?.outputs().get(from.output)?.ty;
            let inp = self.doc.node_type(b)?.inputs().get(to.input)?.ty;
            let (ca, cb) = (self.pin_look(a, out).0, self.pin_look(b, inp).0);
            let mix = |x: u8, y: u8| x.midpoint(y);
            let color = Color32::from_rgba_premultiplied(
                mix(ca.r(), cb.r()),
                mix(ca.g(), cb.g()),
                mix(ca.b(), cb.b()),
                mix(ca.a(), cb.a()),
            );
            Some((from, to, Stroke::new(width, color)))
        });
        self.overview.paint_wires(wires, pin * 3.0, scale);
    }
}

/// `frame` as the overview draws it: without shadow, outline or rounding.
fn plain(frame: egui::Frame) -> egui::Frame {
    frame
        .shadow(egui::Shadow::NONE)
        .stroke(Stroke::NONE)
        .corner_radius(0)
}

impl SnarlViewer<NodeView> for Viewer<'_> {
    fn title(&mut self, node: &NodeView) -> String {
        // The id alone keeps nodes narrow (the bundled graphs leave 200 units per column);
        // the type is in the hover, the header colour and the side panel.
        node.id.clone()
    }

    fn show_header(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        if self.culled(&id) {
            return;
        }
        let errors = self.errors_of(&id);
        let title = self.title(&snarl[node]);
        if self.low_detail() {
            // Painted, not laid out as widgets: each widget registers with egui's context
            // (a lock and hash maps), and a 300-node graph framed whole spent 6 % of its
            // frame on the headers' labels (benches/editor.rs). The node is still selected
            // and dragged by its frame.
            let text = match errors.is_empty() {
                true => title,
                false => format!("{title} ⚠"),
            };
            let font = egui::TextStyle::Body.resolve(ui.style());
            let galley = ui.painter().layout_no_wrap(text, font, Color32::WHITE);
            let (_, rect) = ui.allocate_space(galley.size());
            ui.painter().galley(rect.min, galley, Color32::WHITE);
            return;
        }
        ui.horizontal(|ui| {
            let label = ui.add(
                egui::Label::new(egui::RichText::new(title).strong().color(Color32::WHITE))
                    .sense(egui::Sense::click()),
            );
            if label.clicked() {
                self.actions.push(Action::Focus(id.clone()));
            }
            if !errors.is_empty() {
                ui.label(egui::RichText::new("⚠").color(Color32::from_rgb(255, 90, 80)))
                    .on_hover_text(errors.join("\n"));
            }
            let on = self.swatches.contains_key(&id);
            let toggle = ui
                .selectable_label(on, egui::RichText::new("👁").color(Color32::WHITE))
                .on_hover_text("preview this node's output");
            if toggle.clicked() {
                self.actions.push(Action::TogglePreview(id.clone()));
            }
        });
    }

    fn has_footer(&mut self, node: &NodeView) -> bool {
        self.swatches.contains_key(&node.id) && !self.culled(&node.id)
    }

    fn show_footer(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        let side = egui::vec2(NODE_SWATCH_POINTS, NODE_SWATCH_POINTS);
        match self.swatches.get(&id) {
            Some(Swatch::Image(t)) => {
                ui.image((*t, side));
            }
            Some(Swatch::Message(m)) => {
                ui.add(
                    egui::Label::new(
                        egui::RichText::new(m).color(Color32::from_rgb(255, 120, 110)),
                    )
                    .wrap(),
                );
            }
            Some(Swatch::Pending) | None => {
                ui.allocate_ui(side, |ui| ui.weak("rendering…"));
            }
        }
    }

    fn header_frame(
        &mut self,
        default: egui::Frame,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        snarl: &Snarl<NodeView>,
    ) -> egui::Frame {
        let default = self.frame_for_zoom(default);
        match self.doc.node_type(&snarl[node].id) {
            Some(t) => default.fill(category_color(t.category())),
            None => default.fill(Color32::from_rgb(0x50, 0x20, 0x20)),
        }
    }

    fn node_frame(
        &mut self,
        default: egui::Frame,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        snarl: &Snarl<NodeView>,
    ) -> egui::Frame {
        // The overview's nodes have no shadow, outline or rounding: a pixel or less there,
        // their tessellation was a third of the frame of a 300-node graph framed whole
        // (benches/editor.rs).
        let default = self.frame_for_zoom(default);
        if self.errors_of(&snarl[node].id).is_empty() {
            default
        } else {
            default.stroke(Stroke::new(2.0, Color32::from_rgb(230, 60, 50)))
        }
    }

    fn inputs(&mut self, node: &NodeView) -> usize {
        let all = self.doc.node_type(&node.id).map_or(0, |t| t.inputs().len());
        self.pins_shown(node, all, Culling::inputs)
    }

    fn outputs(&mut self, node: &NodeView) -> usize {
        let all = self
            .doc
            .node_type(&node.id)
            .map_or(0, |t| t.outputs().len());
        self.pins_shown(node, all, Culling::outputs)
    }

    #[allow(refining_impl_trait)]
    fn show_input(&mut self, pin: &InPin, ui: &mut Ui, snarl: &mut Snarl<NodeView>) -> PinInfo {
        let id = self.id(snarl, pin.id.node).to_owned();
        let Some(t) = self.doc.node_type(&id).cloned() else {
            return PinInfo::default();
        };
        let decl = &t.inputs()[pin.id.input];
        let ty = self.doc.port_type(&id, decl.ty);
        let ty_name = ty.map_or("T", |t| t.name());
        let info = self.pin(&id, decl.ty);
        if self.low_detail() || self.culled(&id) {
            return info;
        }
        // Compact editors: the bundled graphs' positions leave ~200 points per column.
        ui.spacing_mut().slider_width = 40.0;
        ui.spacing_mut().interact_size.x = 44.0;
        ui.horizontal(|ui| {
            ui.label(decl.name).on_hover_ui(|ui| {
                ui.label(port_hover(ty_name, decl.unit, decl.doc));
            });
            if pin.remotes.is_empty() {
                let written = self.doc.node(&id).and_then(|n| n.inputs.get(decl.name));
                let ty = ty.unwrap_or(crate::types::SocketType::Float);
                let generic = self
                    .doc
                    .generic(&id)
                    .unwrap_or(crate::types::SocketType::Float);
                let default = t.default_for(pin.id.input, generic);
                let lanes = current_lanes(decl, ty, written, &default);
                if let Some(value) = value_editor(ui, decl, ty, &lanes, self.hard) {
                    self.actions.push(Action::SetInput {
                        node: id.clone(),
                        input: decl.name.to_owned(),
                        value,
                    });
                }
            }
        });
        info
    }

    #[allow(refining_impl_trait)]
    fn show_output(&mut self, pin: &OutPin, ui: &mut Ui, snarl: &mut Snarl<NodeView>) -> PinInfo {
        let id = self.id(snarl, pin.id.node).to_owned();
        let Some(t) = self.doc.node_type(&id).cloned() else {
            return PinInfo::default();
        };
        let decl = &t.outputs()[pin.id.output];
        if self.low_detail() || self.culled(&id) {
            return self.pin(&id, decl.ty);
        }
        let ty_name = self.doc.port_type(&id, decl.ty).map_or("T", |t| t.name());
        // The hover's text is made only when it shows (a 300-node canvas has ~900 pins).
        ui.label(decl.name).on_hover_ui(|ui| {
            ui.label(port_hover(ty_name, decl.unit, decl.doc));
        });
        self.pin(&id, decl.ty)
    }

    fn has_body(&mut self, _: &NodeView) -> bool {
        self.low_detail()
    }

    /// The overview's body: the node's estimated full-detail size, its pins painted on
    /// its edges ([`Body`]).
    fn show_body(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node);
        let (Some(k), Some(t)) = (self.doc.index(id), self.doc.node_type(id)) else {
            return;
        };
        let Some(&(w, h)) = self.doc.node_sizes().get(k) else {
            return;
        };
        let size = egui::vec2((w - BODY_INSET).max(0.0), (h - HEADER_HEIGHT).max(0.0));
        let body = Body(ui.allocate_space(size).1);
        self.overview.record(node, body);
        if self.culled(id) {
            // Off screen: its wires need the body, not the pins.
            return;
        }
        let side = ui.spacing().interact_size.y * 0.6;
        let inputs = t.inputs().iter().enumerate();
        let outputs = t.outputs().iter().enumerate();
        let pins = (inputs.map(|(k, d)| (body.input(k), d.ty)))
            .chain(outputs.map(|(k, d)| (body.output(k), d.ty)));
        let shapes = pins
            .map(|(at, ty)| {
                let (fill, shape) = self.pin_look(id, ty);
                pin_shape(shape, at, side, fill)
            })
            .collect();
        ui.painter().add(Shape::Vec(shapes));
    }

    /// The background pattern, then (in the overview) the slot of the wires, behind the
    /// nodes.
    fn draw_background(
        &mut self,
        background: Option<&BackgroundPattern>,
        viewport: &egui::Rect,
        snarl_style: &SnarlStyle,
        style: &egui::Style,
        painter: &egui::Painter,
        _: &Snarl<NodeView>,
    ) {
        if let Some(background) = background {
            background.draw(viewport, snarl_style, style, painter);
        }
        if self.low_detail() {
            self.overview.reserve(painter);
        }
    }

    /// Imposes the frame-all transform, and culls the nodes away from the viewport (this
    /// is called before any node is drawn).
    fn current_transform(
        &mut self,
        to_global: &mut egui::emath::TSTransform,
        snarl: &mut Snarl<NodeView>,
    ) {
        if let Some(t) = self.set_transform.take() {
            *to_global = t;
        }
        self.to_screen = Some(*to_global);
        self.culling = self.cull(*to_global, snarl);
    }

    fn has_on_hover_popup(&mut self, _: &NodeView) -> bool {
        true
    }

    fn show_on_hover_popup(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        if let Some(t) = self.doc.node_type(&snarl[node].id) {
            ui.strong(format!("{}  ({})", t.name(), t.category()));
            ui.label(t.summary());
        }
    }

    fn connect(&mut self, from: &OutPin, to: &InPin, snarl: &mut Snarl<NodeView>) {
        let (src, dst) = (
            self.id(snarl, from.id.node).to_owned(),
            self.id(snarl, to.id.node).to_owned(),
        );
        let (Some(st), Some(dt)) = (self.doc.node_type(&src), self.doc.node_type(&dst)) else {
            return;
        };
        self.actions.push(Action::Connect {
            from: src,
            output: st.outputs()[from.id.output].name.to_owned(),
            to: dst,
            input: dt.inputs()[to.id.input].name.to_owned(),
        });
    }

    fn disconnect(&mut self, _from: &OutPin, to: &InPin, snarl: &mut Snarl<NodeView>) {
        self.drop_inputs(to, snarl);
    }

    fn drop_inputs(&mut self, pin: &InPin, snarl: &mut Snarl<NodeView>) {
        let id = self.id(snarl, pin.id.node).to_owned();
        if let Some(t) = self.doc.node_type(&id) {
            self.actions.push(Action::Disconnect {
                node: id,
                input: t.inputs()[pin.id.input].name.to_owned(),
            });
        }
    }

    fn drop_outputs(&mut self, pin: &OutPin, snarl: &mut Snarl<NodeView>) {
        for r in &pin.remotes {
            let id = self.id(snarl, r.node).to_owned();
            if let Some(t) = self.doc.node_type(&id) {
                self.actions.push(Action::Disconnect {
                    node: id,
                    input: t.inputs()[r.input].name.to_owned(),
                });
            }
        }
    }

    fn has_graph_menu(&mut self, _: egui::Pos2, _: &mut Snarl<NodeView>) -> bool {
        true
    }

    fn show_graph_menu(&mut self, pos: egui::Pos2, ui: &mut Ui, _: &mut Snarl<NodeView>) {
        self.actions.push(Action::Search {
            pos: [pos.x, pos.y],
            wire: None,
        });
        ui.close();
    }

    fn has_dropped_wire_menu(&mut self, _: AnyPins, _: &mut Snarl<NodeView>) -> bool {
        true
    }

    fn show_dropped_wire_menu(
        &mut self,
        pos: egui::Pos2,
        ui: &mut Ui,
        pins: AnyPins,
        snarl: &mut Snarl<NodeView>,
    ) {
        let wire = match pins {
            AnyPins::Out(&[p, ..]) => {
                let id = self.id(snarl, p.node).to_owned();
                self.doc.node_type(&id).and_then(|t| {
                    let decl = &t.outputs()[p.output];
                    let ty = self.doc.port_type(&id, decl.ty)?;
                    Some((id, decl.name.to_owned(), WireFilter::InputAccepting(ty)))
                })
            }
            AnyPins::In(&[p, ..]) => {
                let id = self.id(snarl, p.node).to_owned();
                self.doc.node_type(&id).and_then(|t| {
                    let decl = &t.inputs()[p.input];
                    let ty = self.doc.port_type(&id, decl.ty)?;
                    Some((id, decl.name.to_owned(), WireFilter::OutputFeeding(ty)))
                })
            }
            _ => None,
        };
        self.actions.push(Action::Search {
            pos: [pos.x, pos.y],
            wire,
        });
        ui.close();
    }

    fn has_node_menu(&mut self, _: &NodeView) -> bool {
        true
    }

    fn show_node_menu(
        &mut self,
        node: NodeId,
        _: &[InPin],
        _: &[OutPin],
        ui: &mut Ui,
        snarl: &mut Snarl<NodeView>,
    ) {
        let id = self.id(snarl, node).to_owned();
        if ui.button("Duplicate").clicked() {
            self.actions.push(Action::Duplicate(vec![id.clone()]));
            ui.close();
        }
        if ui.button("Delete").clicked() {
            self.actions.push(Action::Remove(vec![id.clone()]));
            ui.close();
        }
        if ui.button("Toggle preview").clicked() {
            self.actions.push(Action::TogglePreview(id.clone()));
            ui.close();
        }
        if ui.button("Show docs").clicked() {
            self.actions.push(Action::Focus(id));
            ui.close();
        }
    }
}

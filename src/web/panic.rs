//! A panic in the wasm module shows in the page, not only in the console:
//! after one the module is unusable, and the user must be told. The message
//! goes to `console.error` and, as a [`PANIC_EVENT`] on the window, to the
//! players' error boxes (`www/embusen.js` listens for it).

use wasm_bindgen::JsValue;

/// The `CustomEvent` the window receives on a panic, the message its `detail`.
pub const PANIC_EVENT: &str = "embusen-panic";

/// Installs the panic hook (once, from the module's start).
pub fn install() {
    std::panic::set_hook(Box::new(|info| report_panic(&info.to_string())));
}

/// Logs `message` and sends it to the page as a [`PANIC_EVENT`].
pub fn report_panic(message: &str) {
    let message = JsValue::from_str(message);
    web_sys::console::error_1(&message);
    let Some(window) = web_sys::window() else { return };
    let init = web_sys::CustomEventInit::new();
    init.set_detail(&message);
    // Inside a panic there is no one left to tell when this fails: the console has the message.
    if let Ok(event) = web_sys::CustomEvent::new_with_event_init_dict(PANIC_EVENT, &init) {
        let _ = window.dispatch_event(&event);
    }
}

//! raystep-app's integration tests, one test binary: the actions table driven through the UI
//! (egui_kittest), and the web page's link.

mod app_actions;
mod web_link;

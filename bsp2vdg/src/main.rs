fn main() {
    eprintln!("bsp2vdg: not built yet");
    std::process::exit(1);
}

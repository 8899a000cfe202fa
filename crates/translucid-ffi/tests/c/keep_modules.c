/*
 * Linked into the AddressSanitizer builds only. The Vulkan loader unloads the driver and the
 * validation layer when the instance is destroyed; their global state is then reachable from
 * nowhere and LeakSanitizer reports it as leaked from "<unknown module>". Keeping modules
 * loaded (dlclose does nothing) leaves that state reachable, so every leak still reported is
 * a real one, ours or the driver's.
 */
int dlclose(void *handle);

int dlclose(void *handle) {
    (void)handle;
    return 0;
}
